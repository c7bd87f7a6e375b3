#pragma once
/// Moved to rayproof/verify/gtest.h (link: rayproof::verify and GoogleTest).
/// This forwarding header keeps programs written to the earlier docs building for one release, with
/// a deprecation message, and is removed in the next: change the #include (docs/api.md,
/// Moved headers). RAYPROOF_NO_MOVED_HEADER_MESSAGE defined before the #include silences the message.
#ifndef RAYPROOF_NO_MOVED_HEADER_MESSAGE
#pragma message("rayproof/gtest.h is deprecated: include rayproof/verify/gtest.h instead. The old path works in this release and is removed in the next (docs/api.md, Moved headers).")
#endif
#include "rayproof/verify/gtest.h"
