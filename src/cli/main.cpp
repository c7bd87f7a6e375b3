/// rayproof: fast ray intersection kernels checked against exact arithmetic; every command.
#include "cli/tool.h"

int main(int argc, char** argv) { return rayproof::cli::rayproof_main(argc, argv); }
