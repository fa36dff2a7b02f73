// A fault to inject: LD_PRELOADed into the CLI, libzip's zip_close fails as it would if it could
// not deflate or pack the archive (tests/unit/test_cli.cpp, ThreeMfThatFailsToEncode...). Every
// other libzip function is the real one.
#include <zip.h>

extern "C" int zip_close(zip_t*) { return -1; }
