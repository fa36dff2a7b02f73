// FlatIndex: finds an item among the caller's by its hash, in one cache miss where a node-based
// map (std::unordered_map) takes two or three (a bucket, then a chain of nodes). The one home of
// the generator's open-addressed hashing: linear probing, the table at most half full, doubled when
// it would be more, and insert-if-absent. XyGrid (core/xy_grid.hpp) finds its cells through one,
// ModelQuery (query/model_query.cpp) its remembered answers.
//
// It stores no items, only where they are: the caller keeps them (in a vector, a deque: anything
// addressed by a place 0, 1, 2, ... in the order they were added) and says what equal means. A
// slot is 8 bytes: the place, and the high half of the item's hash, so that a probe past another
// item rarely has to look at it.
//
// Inputs (each call):
//   hash   the item's 64-bit hash, well mixed in its low bits (they pick the first slot) and in its
//          high half (compared before `same` is asked)
//   same   same(place) -> bool: is the stored item at `place` the one asked for?
//   place  (insert) the place the item will take if it is new: the caller's next one
//   hash_of  (insert) hash_of(place) -> the hash given when `place` was inserted (asked for every
//          stored item when the table grows)
// Outputs:
//   find   the place of the stored item `same` accepts, or FlatIndex::npos
//   insert {its place, true} if it was new (recorded at `place`: the caller then stores it
//          there), {the stored item's place, false} if it was there
// Places must be below 2^32 - 1.
//
// Example:
//   std::vector<std::string> names;  // the items
//   FlatIndex index;
//   auto hash = [](const std::string& s) { return std::uint64_t(std::hash<std::string>{}(s)); };
//   auto add = [&](const std::string& s) {
//       auto [at, fresh] = index.insert(hash(s), names.size(), [&](std::size_t i) { return names[i] == s; },
//                                       [&](std::size_t i) { return hash(names[i]); });
//       if (fresh) names.push_back(s);
//       return at;
//   };
//   add("a") == 0, add("b") == 1, add("a") == 0;
//   index.find(hash("b"), [&](std::size_t i) { return names[i] == "b"; }) == 1;
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace cs {

class FlatIndex {
public:
    static constexpr std::size_t npos = ~std::size_t{0};

    template <typename Same>
    std::size_t find(std::uint64_t hash, Same&& same) const {
        if (slots_.empty()) return npos;
        const std::size_t mask = slots_.size() - 1;
        for (std::size_t s = hash & mask; slots_[s] != 0; s = (s + 1) & mask)
            if (const std::size_t at = place_if_high_matches(slots_[s], hash); at != npos && same(at)) return at;
        return npos;
    }

    template <typename Same, typename HashOf>
    std::pair<std::size_t, bool> insert(std::uint64_t hash, std::size_t place, Same&& same, HashOf&& hash_of) {
        if (2 * (size_ + 1) > slots_.size()) grow(hash_of);
        const std::size_t mask = slots_.size() - 1;
        std::size_t s = hash & mask;
        for (; slots_[s] != 0; s = (s + 1) & mask)
            if (const std::size_t at = place_if_high_matches(slots_[s], hash); at != npos && same(at)) return {at, false};
        slots_[s] = slot(hash, place);
        ++size_;
        return {place, true};
    }

    std::size_t size() const { return size_; }

private:
    static constexpr std::uint64_t kHigh = 0xffffffff00000000ull;
    // The place + 1 in the low half (0: an empty slot), the hash's high half above it.
    static std::uint64_t slot(std::uint64_t hash, std::size_t place) { return (hash & kHigh) | (std::uint64_t(place) + 1); }
    static std::size_t place_if_high_matches(std::uint64_t slot, std::uint64_t hash) {
        return (slot & kHigh) == (hash & kHigh) ? static_cast<std::size_t>((slot & ~kHigh) - 1) : npos;
    }
    template <typename HashOf>
    void grow(HashOf& hash_of) {
        std::vector<std::uint64_t> old = std::move(slots_);
        slots_.assign(old.empty() ? 16 : 2 * old.size(), 0);
        const std::size_t mask = slots_.size() - 1;
        for (const std::uint64_t o : old) {
            if (o == 0) continue;
            const std::size_t place = static_cast<std::size_t>((o & ~kHigh) - 1);
            const std::uint64_t h = hash_of(place);
            std::size_t s = h & mask;
            while (slots_[s] != 0) s = (s + 1) & mask;
            slots_[s] = slot(h, place);
        }
    }

    std::vector<std::uint64_t> slots_;  // a power of two of them, or none
    std::size_t size_ = 0;
};

}  // namespace cs
