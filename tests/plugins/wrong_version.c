/* A plugin built against another plugin ABI version (plugin_test: the loader refuses it). */
#include <rayproof/plugin.h>

static void triangle(const double *in, struct rayproof_answer *out) {
  (void)in;
  out->cls = RAYPROOF_COARSE_MISS;
}
static const struct rayproof_kind_fn kinds[] = {{RAYPROOF_KIND_TRIANGLE, triangle, 0}};
static const struct rayproof_plugin plugin = {RAYPROOF_PLUGIN_ABI_VERSION + 1, "future", RAYPROOF_DOUBLE, 1, kinds};
RAYPROOF_PLUGIN_EXPORT const struct rayproof_plugin *rayproof_plugin_entry(void) { return &plugin; }
