/* rayproof/plugin.h must compile as C89 (plugin_test's c89 check compiles this file). */
#include <rayproof/plugin.h>

static void answer(const float *in, struct rayproof_answer *out) {
  out->cls = in[0] < 0.0f ? RAYPROOF_COARSE_HIT : RAYPROOF_COARSE_MISS;
}
static const struct rayproof_kind_fn kinds[] = {{RAYPROOF_KIND_BOX, 0, answer}};
static const struct rayproof_plugin plugin = {RAYPROOF_PLUGIN_ABI_VERSION, "c89", RAYPROOF_FLOAT, 1, kinds};
RAYPROOF_PLUGIN_EXPORT const struct rayproof_plugin *rayproof_plugin_entry(void) { return &plugin; }
