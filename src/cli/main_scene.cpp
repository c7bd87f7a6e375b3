/// rayproof-scene: the whole rayproof tool, the scene commands compiled in (scene_commands.h).
/// `rayproof` runs it for those commands; it can be run directly too.
#include "cli/tool.h"

int main(int argc, char** argv) { return rayproof::cli::rayproof_scene_main(argc, argv); }
