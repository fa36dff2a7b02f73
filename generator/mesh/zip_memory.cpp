#include "mesh/zip_memory.hpp"

#include <algorithm>
#include <cstring>

namespace cs {
namespace {

MemoryZipFile& file_of(voidpf stream) { return *static_cast<MemoryZipFile*>(stream); }

voidpf ZCALLBACK open_file(voidpf opaque, const void*, int) { return opaque; }

uLong ZCALLBACK read_file(voidpf, voidpf stream, void* buf, uLong size) {
    MemoryZipFile& f = file_of(stream);
    const std::size_t n = f.at < f.bytes.size() ? std::min<std::size_t>(size, f.bytes.size() - f.at) : 0;
    if (n) std::memcpy(buf, f.bytes.data() + f.at, n);
    f.at += n;
    return static_cast<uLong>(n);
}

// A write that cannot grow the buffer writes nothing: minizip then fails with ZIP_ERRNO (no
// exception may pass through its C frames).
uLong ZCALLBACK write_file(voidpf, voidpf stream, const void* buf, uLong size) {
    MemoryZipFile& f = file_of(stream);
    try {
        if (f.bytes.size() < f.at + size) f.bytes.resize(f.at + size);
    } catch (...) {
        return 0;
    }
    std::memcpy(f.bytes.data() + f.at, buf, size);
    f.at += size;
    return size;
}

ZPOS64_T ZCALLBACK tell_file(voidpf, voidpf stream) { return file_of(stream).at; }

// 0 on success, -1 for a place before the start or past the end (as fseek on a file opened for
// reading; minizip only seeks within what it has read or written).
long ZCALLBACK seek_file(voidpf, voidpf stream, ZPOS64_T offset, int origin) {
    MemoryZipFile& f = file_of(stream);
    ZPOS64_T base = 0;
    switch (origin) {
        case ZLIB_FILEFUNC_SEEK_SET: base = 0; break;
        case ZLIB_FILEFUNC_SEEK_CUR: base = f.at; break;
        case ZLIB_FILEFUNC_SEEK_END: base = f.bytes.size(); break;
        default: return -1;
    }
    if (offset > f.bytes.size() || base > f.bytes.size() - offset) return -1;
    f.at = static_cast<std::size_t>(base + offset);
    return 0;
}

int ZCALLBACK close_file(voidpf, voidpf) { return 0; }
int ZCALLBACK error_file(voidpf, voidpf) { return 0; }

}  // namespace

zlib_filefunc64_def memory_zip_io(MemoryZipFile& file) {
    zlib_filefunc64_def io{};
    io.zopen64_file = open_file;
    io.zread_file = read_file;
    io.zwrite_file = write_file;
    io.ztell64_file = tell_file;
    io.zseek64_file = seek_file;
    io.zclose_file = close_file;
    io.zerror_file = error_file;
    io.opaque = &file;
    return io;
}

}  // namespace cs
