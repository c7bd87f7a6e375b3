#pragma once
/// A user's kernel as a method: a child process answering case lines over the line protocol of
/// docs/kernel_protocol.md (`--exec NAME=COMMAND`). Each batch streams through a fresh
/// `/bin/sh -c COMMAND` (input written while answers are read, its input closed at the end of the
/// batch, so kernels that buffer until end of input work). A crash, hang, early exit or unreadable
/// answer is pinned on one case by re-running the cases that were in flight one by one in fresh
/// processes (halves first when many were in flight); that case is answered Contact::error and
/// reported through Method::take_failures, and the batch goes on in a restarted kernel.
#include <cstddef>
#include <string>
#include <string_view>
#include <variant>

#include "methods/method.h"

namespace rayproof {

struct ExecOptions {
  double timeout_seconds = 5;     ///< no answer (and no input taken) for this long: the kernel hangs
  std::size_t max_failures = 20;  ///< after this many failures in one run the kernel is dropped
};

/// The method for `NAME=COMMAND` (the kernel declares precision and kinds on its first output line)
/// or `NAME:PRECISION:KIND[,KIND...]=COMMAND`. When the spec declares nothing, the kernel is started
/// once here (its input closed at once) to read its declaration. Gives the method, or a message
/// saying what is wrong with the spec or the declaration. Ignores SIGPIPE in this process (a kernel
/// that exits while rayproof writes must not kill rayproof); children get the default back.
/// The method is safe to call from several threads at once (each batch has its own process).
[[nodiscard]] std::variant<Method, std::string> make_exec_method(std::string_view spec, const ExecOptions& opt = {});

}  // namespace rayproof
