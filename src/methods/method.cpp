#include "methods/method.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rayproof {

std::string Promise::describe() const {
  std::string s;
  auto add = [&](const std::string& part) { s += (s.empty() ? "" : ", ") + part; };
  if (exact_class) add("exact class");
  if (!exact_class && no_false_miss == NoFalseMiss::all) add("no false miss");
  if (!exact_class && no_false_miss == NoFalseMiss::ahead) add("no false miss ahead of the origin (coplanar rays excepted)");
  if (t_ulps) add(*t_ulps == 1 ? std::string("t within 1 ulp") : "t within " + std::to_string(*t_ulps) + " ulps");
  return s.empty() ? "nothing" : s;
}

std::map<io::Kind, Promise> exact_promises() {
  std::map<io::Kind, Promise> m;
  for (io::Kind k : io::kCaseKinds) m[k] = Promise{true, Promise::NoFalseMiss::all, 1};
  return m;
}

Promise Method::promise(io::Kind k) const {
  const auto it = promises.find(k);
  return it == promises.end() ? Promise{} : it->second;
}

bool Method::supports(io::Kind k) const { return std::find(kinds.begin(), kinds.end(), k) != kinds.end(); }

io::CaseResult Method::run(const io::Case& c) const {
  if (!supports(c.kind)) return {Contact::error};
  if (precision == Precision::float32) return classify(io::round_to_float(c));
  return classify(c);
}

void Method::classify_many(std::span<const io::Case> in, std::span<io::CaseResult> out) const {
  if (classify_batch) return classify_batch(in, out);
  for (std::size_t i = 0; i < in.size(); ++i) out[i] = classify(in[i]);
}

void MethodRegistry::add(Method m) {
  if (find(m.name)) throw std::logic_error("method registered twice: " + m.name);
  methods_.push_back(std::move(m));
}

const Method* MethodRegistry::find(const std::string& name) const {
  for (const auto& m : methods_)
    if (m.name == name) return &m;
  return nullptr;
}

std::string MethodRegistry::names() const {
  std::string s;
  for (const auto& m : methods_) s += (s.empty() ? "" : ", ") + m.name;
  return s;
}

io::CaseResult make_result(io::Kind kind, Contact c, double t, double t2) {
  io::CaseResult r{c, std::nullopt, std::nullopt};
  const bool two = kind == io::Kind::sphere || kind == io::Kind::ellipsoid || kind == io::Kind::box;
  switch (c) {
    case Contact::coplanar:
      if (kind == io::Kind::triangle && !(std::isnan(t) && std::isnan(t2))) r.t = t, r.t2 = t2;
      break;
    case Contact::behind: case Contact::hit: case Contact::interior: case Contact::edge:
    case Contact::vertex: case Contact::rim: case Contact::tangent: case Contact::inside:
    case Contact::graze:
      r.t = t;
      if (two) r.t2 = t2;
      break;
    default:
      break;
  }
  return r;
}

}  // namespace rayproof
