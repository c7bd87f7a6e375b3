/* A plugin declaring a kind that does not exist (plugin_test: the loader refuses it). */
#include <rayproof/plugin.h>

static void answer(const double *in, struct rayproof_answer *out) {
  (void)in;
  out->cls = RAYPROOF_COARSE_MISS;
}
static const struct rayproof_kind_fn kinds[] = {{RAYPROOF_KIND_TRIANGLE, answer, 0}, {7, answer, 0}};
static const struct rayproof_plugin plugin = {RAYPROOF_PLUGIN_ABI_VERSION, "bad-kind", RAYPROOF_DOUBLE, 2, kinds};
RAYPROOF_PLUGIN_EXPORT const struct rayproof_plugin *rayproof_plugin_entry(void) { return &plugin; }
