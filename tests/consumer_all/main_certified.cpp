// core and certified only (also built with pkg-config flags).
#include <cstdio>

#include "checks.h"

int main() {
  const int failures = check_core() + check_certified();
  std::printf("consumer_certified: %d failures\n", failures);
  return failures == 0 ? 0 : 1;
}
