// core/sha256: the FIPS 180-4 test vectors, and a file hashed as its bytes.
#include <gtest/gtest.h>

#include <fstream>

#include "core/sha256.hpp"
#include "support.hpp"

using namespace cs;

TEST(Sha256, FipsTestVectors) {
    EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    // Two blocks: the padding spills into a second one.
    EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
              "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

TEST(Sha256, ManyWholeBlocksThenTheTail) {
    // FIPS 180-4's long vector: a million 'a', 15,625 whole blocks read in place, then the padding.
    EXPECT_EQ(sha256_hex(std::string(1000000, 'a')), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256, AFileHashesAsItsBytes) {
    cs::test::TempDir tmp;
    const std::string path = tmp.path + "/a.bin";
    std::ofstream(path, std::ios::binary) << "abc";
    EXPECT_EQ(file_sha256(path), sha256_hex("abc"));
}

// The CPU's SHA instructions (where it has them) give the portable code's digest: every length
// around a block and its padding, and a few whole blocks of every byte value.
TEST(Sha256, TheFastPathGivesThePortableDigest) {
    std::string bytes;
    for (int i = 0; i < 600; ++i) bytes.push_back(static_cast<char>((i * 131 + 7) & 0xff));
    for (std::size_t n = 0; n <= bytes.size(); n += (n < 200 ? 1 : 37)) {
        const std::string_view v(bytes.data(), n);
        EXPECT_EQ(sha256_hex(v), sha256_hex(v, Sha256Path::portable)) << n;
    }
}
