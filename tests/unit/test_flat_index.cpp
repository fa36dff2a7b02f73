// core/flat_index.hpp: the one open-addressed index (XyGrid's cells, ModelQuery's remembered
// answers). Whatever the hashes, it must find what std::unordered_map finds: every item inserted
// at the place it was given, a repeat at the first one's place, nothing for an item never added.
#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/flat_index.hpp"

namespace cs {
namespace {

// Items kept by the caller in a vector; `hash` decides how they collide.
struct Names {
    std::function<std::uint64_t(std::uint64_t)> hash;
    std::vector<std::uint64_t> items;
    FlatIndex index;
    std::pair<std::size_t, bool> add(std::uint64_t x) {
        const auto r = index.insert(
            hash(x), items.size(), [&](std::size_t i) { return items[i] == x; }, [&](std::size_t i) { return hash(items[i]); });
        if (r.second) items.push_back(x);
        return r;
    }
    std::size_t find(std::uint64_t x) const {
        return index.find(hash(x), [&](std::size_t i) { return items[i] == x; });
    }
};

std::uint64_t mixed(std::uint64_t k) {
    k ^= k >> 33, k *= 0xff51afd7ed558ccdull, k ^= k >> 33;
    return k;
}

// Against std::unordered_map, with hashes well mixed, sharing their high half (every probe asks
// `same`), sharing their low bits (every item in one run of slots) and all equal.
TEST(FlatIndex, FindsWhatAMapFindsWhateverTheHashes) {
    const std::vector<std::pair<const char*, std::function<std::uint64_t(std::uint64_t)>>> hashes = {
        {"mixed", mixed},
        {"same high half", [](std::uint64_t k) { return mixed(k) & 0xffffffffull; }},
        {"same low bits", [](std::uint64_t k) { return mixed(k) << 20; }},
        {"all equal", [](std::uint64_t) { return std::uint64_t{0x1234567890abcdefull}; }},
    };
    for (const auto& [what, hash] : hashes) {
        SCOPED_TRACE(what);
        const bool slow = std::string(what) == "all equal" || std::string(what) == "same low bits";
        const int n = slow ? 600 : 20000;
        std::mt19937_64 rng(7);
        Names names{hash, {}, {}};
        std::unordered_map<std::uint64_t, std::size_t> map;
        for (int k = 0; k < 3 * n; ++k) {
            const std::uint64_t x = rng() % n;  // many repeats
            const auto [at, fresh] = names.add(x);
            const auto [it, map_fresh] = map.try_emplace(x, map.size());
            ASSERT_EQ(fresh, map_fresh);
            ASSERT_EQ(at, it->second);
            ASSERT_EQ(names.items[at], x);
        }
        EXPECT_EQ(names.index.size(), map.size());
        for (std::uint64_t x = 0; x < std::uint64_t(n) + 100; ++x) {
            const auto it = map.find(x);
            EXPECT_EQ(names.find(x), it == map.end() ? FlatIndex::npos : it->second) << x;
        }
    }
}

TEST(FlatIndex, EmptyFindsNothing) {
    const FlatIndex index;
    EXPECT_EQ(index.find(42, [](std::size_t) { return true; }), FlatIndex::npos);
    EXPECT_EQ(index.size(), 0u);
}

// The header's example.
TEST(FlatIndex, HeadersExample) {
    std::vector<std::string> names;
    FlatIndex index;
    auto hash = [](const std::string& s) { return std::uint64_t(std::hash<std::string>{}(s)); };
    auto add = [&](const std::string& s) {
        auto [at, fresh] = index.insert(hash(s), names.size(), [&](std::size_t i) { return names[i] == s; },
                                        [&](std::size_t i) { return hash(names[i]); });
        if (fresh) names.push_back(s);
        return at;
    };
    EXPECT_EQ(add("a"), 0u);
    EXPECT_EQ(add("b"), 1u);
    EXPECT_EQ(add("a"), 0u);
    EXPECT_EQ(index.find(hash("b"), [&](std::size_t i) { return names[i] == "b"; }), 1u);
    EXPECT_EQ(index.find(hash("c"), [&](std::size_t i) { return names[i] == "c"; }), FlatIndex::npos);
}

}  // namespace
}  // namespace cs
