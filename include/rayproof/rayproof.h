#pragma once
/// Every fast kernel of rayproof::core.
#include "rayproof/box.h"
#include "rayproof/camera.h"
#include "rayproof/disk.h"
#include "rayproof/ellipsoid.h"
#include "rayproof/plane.h"
#include "rayproof/sphere.h"
#include "rayproof/triangle.h"
#include "rayproof/tritri.h"
