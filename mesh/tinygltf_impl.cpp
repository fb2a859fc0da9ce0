// tinygltf's implementation (Debian's header-only libtinygltf-dev), compiled here once so that
// the fuzz and sanitizer builds instrument it too. Without image decoding: meshtour keeps the
// images' encoded bytes (OpenImageIO reads them) and opens external images itself, by path.
#define TINYGLTF_IMPLEMENTATION
#include "mesh/tinygltf_config.h"
