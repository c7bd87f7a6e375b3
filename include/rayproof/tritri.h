#pragma once
/// One front door for the classic triangle/triangle tests in float or double: does the closed
/// triangle a meet the closed triangle b? tritri_intersect(a, b, TriTriMethod). They answer with
/// plain floating point and can be wrong near contact (docs/tritri.md measures how often); the
/// exact class is rayproof/certified/tritri.h's.
#include "rayproof/tritri_class.h"
#include "rayproof/tritri_guigue_devillers.h"
#include "rayproof/tritri_moller.h"

namespace rayproof {

enum class TriTriMethod { moller, guigue_devillers };

template <class T>
[[nodiscard]] bool tritri_intersect(const Triangle<T>& a, const Triangle<T>& b,
                                    TriTriMethod m = TriTriMethod::guigue_devillers) {
  switch (m) {
    case TriTriMethod::moller: return tritri_moller(a, b);
    case TriTriMethod::guigue_devillers: break;
  }
  return tritri_guigue_devillers(a, b);
}

}  // namespace rayproof
