#include "test_paths.hpp"

namespace drape::test {

const char* sourceDir() {
  return DRAPE_SOURCE_DIR;
}
const char* drapeBinary() {
  return DRAPE_BINARY;
}

}  // namespace drape::test
