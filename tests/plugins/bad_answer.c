/* A plugin answering outside the vocabulary: class 99 when the origin's x is negative, a coarse
 * miss otherwise (plugin_test: a kernel failure with the case, not a crash). */
#include <rayproof/plugin.h>

static void triangle(const double *in, struct rayproof_answer *out) {
  out->cls = in[0] < 0.0 ? 99 : RAYPROOF_COARSE_MISS;
}
static const struct rayproof_kind_fn kinds[] = {{RAYPROOF_KIND_TRIANGLE, triangle, 0}};
static const struct rayproof_plugin plugin = {RAYPROOF_PLUGIN_ABI_VERSION, "bad-answer", RAYPROOF_DOUBLE, 1, kinds};
RAYPROOF_PLUGIN_EXPORT const struct rayproof_plugin *rayproof_plugin_entry(void) { return &plugin; }
