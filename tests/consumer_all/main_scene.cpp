// The scene component alone (built with pkg-config's rayproof-scene flags only).
#include <cstdio>

#include "checks.h"

int main() {
  const int failures = check_scene();
  std::printf("consumer_scene: %d failures\n", failures);
  return failures == 0 ? 0 : 1;
}
