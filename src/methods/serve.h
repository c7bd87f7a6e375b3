#pragma once
/// The kernel side of the line protocol (docs/kernel_protocol.md) for a method rayproof already has
/// in process: `rayproof serve --method NAME` and the plugin host use it, so that a built-in method
/// or a plugin can be put under test through `--exec` exactly as a user's program is.
#include <iosfwd>

#include "methods/method.h"

namespace rayproof {

/// Writes the declaration line `rayproof-kernel 1 PRECISION KINDS` when `header`, then answers every
/// case line of `in` with `m.run` (float methods see float-rounded inputs, as over --exec) as a
/// full `CLASS T T2` line, or a coarse `hit T B1 B2` ... `miss` line for a coarse answer
/// (io::format_answer), until end of input. A line that cannot be read, or a kind the method does
/// not answer, gets `error - -`; an answer the method reports as a kernel failure (a plugin's answer
/// outside the vocabulary, take_failures) gets `kernel-failure: WHAT`, which is no answer. Returns 0.
int serve_kernel_protocol(const Method& m, std::istream& in, std::ostream& out, bool header = true);

}  // namespace rayproof
