/* A float plugin that gives only a double function (plugin_test: the loader refuses it). */
#include <rayproof/plugin.h>

static void answer(const double *in, struct rayproof_answer *out) {
  (void)in;
  out->cls = RAYPROOF_COARSE_MISS;
}
static const struct rayproof_kind_fn kinds[] = {{RAYPROOF_KIND_SPHERE, answer, 0}};
static const struct rayproof_plugin plugin = {RAYPROOF_PLUGIN_ABI_VERSION, "bad-precision", RAYPROOF_FLOAT, 1, kinds};
RAYPROOF_PLUGIN_EXPORT const struct rayproof_plugin *rayproof_plugin_entry(void) { return &plugin; }
