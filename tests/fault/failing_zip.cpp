// A fault to inject: LD_PRELOADed into the CLI, minizip's zipClose fails as it would if it could
// not write the archive's directory (tests/unit/test_cli.cpp, ThreeMfThatFailsToEncode...). The
// real zipClose still runs first, so the archive is freed as a failing close frees it (the
// sanitizer build's leak check would fail the run otherwise). Every other minizip function is the
// real one.
#include <dlfcn.h>
#include <minizip/zip.h>

extern "C" int zipClose(zipFile file, const char* comment) {
    using Close = int (*)(zipFile, const char*);
    static const auto real = reinterpret_cast<Close>(dlsym(RTLD_NEXT, "zipClose"));
    if (real) real(file, comment);
    return ZIP_ERRNO;
}
