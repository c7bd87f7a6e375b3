/* A shared library without the plugin entry point (plugin_test: the loader says so). */
int rayproof_plugin_entry_misspelled(void) { return 1; }
