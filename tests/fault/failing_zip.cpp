// A fault to inject: LD_PRELOADed into the CLI, minizip's zipClose fails as it would if it could
// not write the archive's directory (tests/unit/test_cli.cpp, ThreeMfThatFailsToEncode...). Every
// other minizip function is the real one.
#include <minizip/zip.h>

extern "C" int zipClose(zipFile, const char*) { return ZIP_ERRNO; }
