// ZIP archives held in memory, for minizip (zlib's contrib/minizip, Debian's libminizip): the file
// functions minizip reads and writes an archive through, over a std::string instead of a file.
// 3MF files are ZIP archives: mesh/read_3mf.cpp unpacks one it was given, output/threemf.cpp packs
// the ones it writes.
//
// Example (writing; reading is the same with the archive's bytes in `file.bytes`):
//   MemoryZipFile file;
//   zlib_filefunc64_def io = memory_zip_io(file);
//   zipFile z = zipOpen2_64("archive", APPEND_STATUS_CREATE, nullptr, &io);
//   ... zipOpenNewFileInZip ... zipWriteInFileInZip ... zipCloseFileInZip ... zipClose(z, nullptr);
//   // file.bytes is the archive
#pragma once

#include <minizip/ioapi.h>

#include <cstddef>
#include <string>

namespace cs {

// The archive's bytes and where minizip is in them. It must outlive the zipFile / unzFile opened
// on it. A write past the end grows it; a write inside overwrites (minizip goes back to a local
// header to fill in the sizes and CRC once an entry is deflated).
struct MemoryZipFile {
    std::string bytes;
    std::size_t at = 0;
};

// File functions over `file` (the name given to zipOpen2_64 / unzOpen2_64 is not used).
zlib_filefunc64_def memory_zip_io(MemoryZipFile& file);

}  // namespace cs
