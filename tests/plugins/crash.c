/* A plugin that crashes (SIGSEGV through a null pointer) when the origin's x is negative and
 * answers a coarse miss otherwise (plugin_test: run forked through plugin-host, never in process). */
#include <rayproof/plugin.h>

static void triangle(const double *in, struct rayproof_answer *out) {
  volatile int *nowhere = 0;
  if (in[0] < 0.0) *nowhere = 1;
  out->cls = RAYPROOF_COARSE_MISS;
}
static const struct rayproof_kind_fn kinds[] = {{RAYPROOF_KIND_TRIANGLE, triangle, 0}};
static const struct rayproof_plugin plugin = {RAYPROOF_PLUGIN_ABI_VERSION, "crash", RAYPROOF_DOUBLE, 1, kinds};
RAYPROOF_PLUGIN_EXPORT const struct rayproof_plugin *rayproof_plugin_entry(void) { return &plugin; }
