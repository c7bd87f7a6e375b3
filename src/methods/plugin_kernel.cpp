#include "methods/plugin_kernel.h"

#include <dlfcn.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string_view>
#include <system_error>
#include <vector>

namespace rayproof {

namespace {

// plugin.h's numbers are the enums' values (C cannot include the C++ headers).
static_assert(RAYPROOF_KIND_TRITRI == static_cast<int>(io::Kind::tritri) && io::kCaseKinds.size() == 7);
static_assert(RAYPROOF_RIM == static_cast<int>(Contact::rim) && RAYPROOF_DISJOINT == static_cast<int>(Contact::disjoint) &&
              RAYPROOF_CROSSING == static_cast<int>(Contact::crossing) &&
              RAYPROOF_TOUCHING == static_cast<int>(Contact::touching) &&
              RAYPROOF_COPLANAR_OVERLAP == static_cast<int>(Contact::coplanar_overlap) &&
              RAYPROOF_COPLANAR_TOUCHING == static_cast<int>(Contact::coplanar_touching));

/// What classify needs: the kind functions and the failures not yet taken.
struct PluginState {
  Precision precision = Precision::float64;
  std::array<rayproof_double_fn, io::kCaseKinds.size()> on_double{};
  std::array<rayproof_float_fn, io::kCaseKinds.size()> on_float{};
  std::mutex mutex;
  std::vector<KernelFailure> failures;  ///< at most kMaxKept between two takes; later ones are not kept
};

constexpr std::size_t kMaxKept = 10000;

bool good_name(std::string_view s) {
  if (s.empty() || s.size() > 64) return false;
  return std::all_of(s.begin(), s.end(), [](char ch) {
    return (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '_' ||
           ch == '.' || ch == '+' || ch == '-';
  });
}

/// The declared name, read only up to 65 characters (a pointer to garbage must not run away).
std::string bounded_name(const char* p) {
  std::string s;
  if (!p) return s;
  for (std::size_t i = 0; i <= 64 && p[i]; ++i) s += p[i];
  return s;
}

std::string printable(std::string_view s) {
  std::string out;
  for (char ch : s) out += (ch >= 0x20 && ch < 0x7f) ? ch : '?';
  return out;
}

io::CaseResult call(PluginState& st, const io::Case& c) {
  rayproof_answer a{RAYPROOF_NO_ANSWER, 0, 0.0, 0.0, 0.0, 0.0};
  const auto k = static_cast<std::size_t>(c.kind);
  if (st.precision == Precision::float64) {
    if (!st.on_double[k]) return {Contact::error};  // a kind the plugin does not answer
    st.on_double[k](c.v.data(), &a);
  } else {
    if (!st.on_float[k]) return {Contact::error};
    std::array<float, io::kMaxFields> in{};
    for (std::size_t i = 0; i < in.size(); ++i) in[i] = static_cast<float>(c.v[i]);
    st.on_float[k](in.data(), &a);
  }
  auto r = plugin_answer_to_result(c.kind, a);
  if (auto* ok = std::get_if<io::CaseResult>(&r)) return *ok;
  std::lock_guard lock(st.mutex);
  if (st.failures.size() < kMaxKept) st.failures.push_back({std::get<std::string>(r), c});
  return {Contact::error};
}

/// A word for /bin/sh: in single quotes, a quote inside as '\''.
std::string shell_word(const std::string& s) {
  std::string out = "'";
  for (char ch : s) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return out + "'";
}

}  // namespace

std::variant<io::CaseResult, std::string> plugin_answer_to_result(io::Kind kind, const rayproof_answer& a) {
  io::CaseResult r;
  const int known_bits = RAYPROOF_HAS_T | RAYPROOF_HAS_T2 | RAYPROOF_HAS_B;
  if (a.has & ~known_bits) return "answer outside the vocabulary: unknown bits in has (" + std::to_string(a.has) + ")";
  const bool has_t = a.has & RAYPROOF_HAS_T, has_t2 = a.has & RAYPROOF_HAS_T2, has_b = a.has & RAYPROOF_HAS_B;
  if (kind == io::Kind::tritri) {  // a pair: hit or miss, or its class alone, never with values
    const bool pair_class = a.cls == RAYPROOF_INVALID || a.cls == RAYPROOF_DEGENERATE ||
                            (a.cls >= RAYPROOF_DISJOINT && a.cls <= RAYPROOF_COPLANAR_TOUCHING);
    const bool coarse = a.cls == RAYPROOF_COARSE_HIT || a.cls == RAYPROOF_COARSE_MISS;
    if ((pair_class || coarse) && a.has) return std::string("answer outside the vocabulary: values (has) on a tritri answer");
    if (pair_class) return io::pair_result(static_cast<Contact>(a.cls));
    if (coarse) return io::pair_coarse(a.cls == RAYPROOF_COARSE_HIT);
    if (a.cls >= RAYPROOF_INVALID && a.cls <= RAYPROOF_RIM)
      return "not an answer to a tritri case: the ray class " + std::string(to_string(static_cast<Contact>(a.cls)));
  } else if (a.cls >= RAYPROOF_DISJOINT && a.cls <= RAYPROOF_COPLANAR_TOUCHING) {
    return "not an answer to a " + std::string(io::to_string(kind)) + " case: the pair class " +
           std::string(to_string(static_cast<Contact>(a.cls)));
  }
  if (a.cls >= RAYPROOF_INVALID && a.cls <= RAYPROOF_RIM) {
    if (has_b) return "answer outside the vocabulary: barycentrics on a full answer (" +
                      std::string(to_string(static_cast<Contact>(a.cls))) + ")";
    r.contact = static_cast<Contact>(a.cls);
    if (has_t) r.t = a.t;
    if (has_t2) r.t2 = a.t2;
    return r;
  }
  r.form = io::AnswerForm::coarse;
  if (a.cls == RAYPROOF_COARSE_MISS) {
    if (a.has) return std::string("answer outside the vocabulary: a coarse miss with values");
    r.contact = Contact::miss;
    return r;
  }
  if (a.cls == RAYPROOF_COARSE_HIT) {
    if (has_t2) return std::string("answer outside the vocabulary: T2 on a coarse hit");
    if (has_b && !has_t) return std::string("answer outside the vocabulary: barycentrics without t on a coarse hit");
    if (has_b && kind != io::Kind::triangle)
      return "answer outside the vocabulary: barycentrics on a " + std::string(io::to_string(kind)) + " hit";
    r.contact = Contact::hit;
    if (has_t) r.t = a.t;
    if (has_b) r.b1 = a.b1, r.b2 = a.b2;
    return r;
  }
  if (a.cls == RAYPROOF_NO_ANSWER) return std::string("no answer written (cls left at RAYPROOF_NO_ANSWER)");
  return "answer outside the vocabulary: unknown class " + std::to_string(a.cls);
}

std::variant<Method, std::string> load_plugin_method(const std::string& path, const std::string& name) {
  const std::string where = "plugin " + path;
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return where + ": no such file";
  if (std::filesystem::is_directory(path, ec)) return where + ": is a directory, not a shared library";
  // A bare file name would make dlopen search the library path: always name the file itself.
  const std::string open_path = path.find('/') == std::string::npos ? "./" + path : path;
  dlerror();
  void* lib = dlopen(open_path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!lib) {
    const char* why = dlerror();
    return where + ": cannot load it as a shared library (" + (why ? why : "unknown reason") + ")";
  }
  dlerror();
  void* sym = dlsym(lib, RAYPROOF_PLUGIN_ENTRY_NAME);
  if (!sym) {
    dlclose(lib);
    return where + ": no entry point " RAYPROOF_PLUGIN_ENTRY_NAME
                   " (see rayproof/plugin.h; in C++ declare it with RAYPROOF_PLUGIN_EXPORT for C linkage)";
  }
  // The library stays loaded from here on: its functions are called until rayproof exits.
  auto entry = reinterpret_cast<rayproof_plugin_entry_fn>(sym);
  const rayproof_plugin* p = entry();
  if (!p) return where + ": " RAYPROOF_PLUGIN_ENTRY_NAME " returned no description (a null pointer)";
  if (p->abi_version != RAYPROOF_PLUGIN_ABI_VERSION)
    return where + ": built for plugin ABI version " + std::to_string(p->abi_version) + ", this rayproof loads version " +
           std::to_string(RAYPROOF_PLUGIN_ABI_VERSION) + " (rebuild it against this rayproof's rayproof/plugin.h)";
  const std::string declared = bounded_name(p->name);
  if (!good_name(declared))
    return where + ": bad name '" + printable(declared) + "' (1 to 64 characters of A-Z a-z 0-9 _ . + -)";
  if (p->precision != RAYPROOF_FLOAT && p->precision != RAYPROOF_DOUBLE)
    return where + ": bad precision " + std::to_string(p->precision) + " (RAYPROOF_FLOAT or RAYPROOF_DOUBLE)";
  if (p->kind_count < 1 || p->kind_count > static_cast<int>(io::kCaseKinds.size()) || !p->kinds)
    return where + ": bad kind list (kind_count " + std::to_string(p->kind_count) + "; 1 to 7 kinds)";

  auto st = std::make_shared<PluginState>();
  st->precision = p->precision == RAYPROOF_FLOAT ? Precision::float32 : Precision::float64;
  std::vector<io::Kind> kinds;
  for (int i = 0; i < p->kind_count; ++i) {
    const rayproof_kind_fn& k = p->kinds[i];
    if (k.kind < RAYPROOF_KIND_PLANE || k.kind > RAYPROOF_KIND_TRITRI)
      return where + ": bad kind " + std::to_string(k.kind) + " (RAYPROOF_KIND_PLANE .. RAYPROOF_KIND_TRITRI)";
    const auto kind = static_cast<io::Kind>(k.kind);
    if (std::find(kinds.begin(), kinds.end(), kind) != kinds.end())
      return where + ": kind " + std::string(io::to_string(kind)) + " declared twice";
    const bool has_fn = st->precision == Precision::float64 ? k.on_double != nullptr : k.on_float != nullptr;
    if (!has_fn)
      return where + ": kind " + std::string(io::to_string(kind)) + " has no " +
             (st->precision == Precision::float64 ? "on_double" : "on_float") + " function (the plugin is " +
             (st->precision == Precision::float64 ? "double" : "float") + ")";
    if (st->precision == Precision::float64) {
      st->on_double[static_cast<std::size_t>(kind)] = k.on_double;
    } else {
      st->on_float[static_cast<std::size_t>(kind)] = k.on_float;
    }
    kinds.push_back(kind);
  }
  std::sort(kinds.begin(), kinds.end());

  Method m;
  m.name = name.empty() ? declared : name;
  m.summary = "plugin " + path + (declared == m.name ? std::string() : " ('" + declared + "')");
  m.precision = st->precision;
  m.kinds = std::move(kinds);
  m.classify = [st](const io::Case& c) { return call(*st, c); };
  m.take_failures = [st] {
    std::vector<KernelFailure> out;
    std::lock_guard lock(st->mutex);
    out.swap(st->failures);
    return out;
  };
  return m;
}

std::variant<Method, std::string> make_forked_plugin_method(const std::string& path, const std::string& name,
                                                           const std::string& host, const ExecOptions& opt) {
  // Checked here so that a typo gets this message rather than the child's.
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return "plugin " + path + ": no such file";
  const std::string method_name = name.empty() ? std::filesystem::path(path).stem().string() : name;
  const std::string absolute = std::filesystem::absolute(path, ec).string();
  // `exec`: the shell becomes the host, so that a crash is reported as the host's signal.
  auto made = make_exec_method(method_name + "=exec " + shell_word(host) + " plugin-host " + shell_word(absolute), opt);
  if (auto* why = std::get_if<std::string>(&made)) return "plugin " + path + " (forked): " + *why;
  Method& m = std::get<Method>(made);
  m.summary = "plugin " + path + ", run in child processes (rayproof plugin-host)";
  return std::move(m);
}

}  // namespace rayproof
