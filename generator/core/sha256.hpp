// SHA-256 (FIPS 180-4) of bytes or of a file, as 64 lowercase hex digits: the report and the
// .scad header name their input by it, and `regrow` warns when the input has changed since.
// A small self-contained implementation (no crypto library is needed for naming a file).
//   sha256_hex("abc") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
#pragma once

#include <string>
#include <string_view>

namespace cs {

// `path`: the CPU's SHA instructions where it has them (x86-64), else the portable code; tests
// compare the two. The same digest either way.
enum class Sha256Path { fastest, portable };
std::string sha256_hex(std::string_view bytes, Sha256Path path = Sha256Path::fastest);
// An unreadable file hashes as no bytes (callers read the file themselves first).
std::string file_sha256(const std::string& path);

}  // namespace cs
