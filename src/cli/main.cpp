/// rayproof: fast ray intersection kernels checked against exact arithmetic. This executable holds
/// the case-level commands; the scene commands run in rayproof-scene beside it (scene_commands.h).
#include "cli/tool.h"

int main(int argc, char** argv) { return rayproof::cli::rayproof_main(argc, argv); }
