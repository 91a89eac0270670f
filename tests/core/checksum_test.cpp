// The checksums of the provenance (SHA-256 of the scene, CRC-32 of the PNG chunk): the plain
// statements that the browser's build runs are held to the standards' own test vectors and to
// the libraries the native build links.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "svetlo/core/crc32.h"
#include "svetlo/core/sha256.h"

using namespace svetlo;

namespace {

uint32_t crc_of(const std::string& s, bool plain) {
    const auto* d = reinterpret_cast<const unsigned char*>(s.data());
    return plain ? crc32_plain(d, s.size()) : crc32_of(d, s.size());
}

}  // namespace

// FIPS 180-4's examples (NIST's SHA-256 example values): one block, two blocks, a million a's.
TEST(Checksums, Sha256OfTheStandardsExamples) {
    for (bool plain : {false, true}) {
        auto hash = [&](const std::string& s) {
            return plain ? sha256_hex_plain(s) : sha256_hex(s);
        };
        EXPECT_EQ(hash(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
        EXPECT_EQ(hash("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
        EXPECT_EQ(hash("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
                  "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
        EXPECT_EQ(hash(std::string(1000000, 'a')),
                  "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
    }
}

// Every length around the padding's edges (55, 56, 63, 64 bytes and their multiples).
TEST(Checksums, Sha256PlainAgreesAtEveryLengthNearABlock) {
    std::mt19937 rng(7);
    for (size_t n = 0; n <= 200; ++n) {
        std::string s(n, '\0');
        for (char& c : s) c = static_cast<char>(rng());
        EXPECT_EQ(sha256_hex_plain(s), sha256_hex(s)) << n << " bytes";
    }
}

// The CRC-32 check value (ISO 3309 / ITU-T V.42: "123456789" -> CBF43926) and the PNG
// specification's IEND chunk, whose CRC every PNG ends with (AE426082).
TEST(Checksums, Crc32OfTheStandardsExamples) {
    for (bool plain : {false, true}) {
        EXPECT_EQ(crc_of("", plain), 0u);
        EXPECT_EQ(crc_of("123456789", plain), 0xCBF43926u);
        EXPECT_EQ(crc_of("IEND", plain), 0xAE426082u);
    }
    std::mt19937 rng(11);
    std::string s(5000, '\0');
    for (char& c : s) c = static_cast<char>(rng());
    EXPECT_EQ(crc_of(s, true), crc_of(s, false));
}
