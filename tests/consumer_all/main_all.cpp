// Every component: core, certified, verify, scene.
#include <cstdio>

#include "checks.h"

int main() {
  const int failures = check_core() + check_certified() + check_verify() + check_scene();
  std::printf("consumer_all: %d failures\n", failures);
  return failures == 0 ? 0 : 1;
}
