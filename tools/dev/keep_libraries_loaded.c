/* Preloaded by tools/dev/sanitize.sh: dlclose does nothing, so every shared library stays loaded until
 * the process exits. The Vulkan loader unloads the driver (lavapipe) and the validation layer when an
 * instance is destroyed; LeakSanitizer, which looks for leaks at exit, would then find the blocks
 * those libraries still point to from their own globals unreferenced, and report them as leaks
 * allocated from "<unknown module>". With the libraries kept, those blocks are reachable and any
 * real leak keeps a stack LeakSanitizer can name. */
int dlclose(void* handle) {
  (void)handle;
  return 0;
}
