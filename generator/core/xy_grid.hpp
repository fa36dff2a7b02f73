// A uniform hash grid over the XY plane: items filed by the square cell their point falls in.
//
// Every "what is near this point, seen from above" question of the generator and the judge asks
// one: the sweep's active nodes (tree/), the samples that cover an overhang point (overhang/),
// the contacts near a point and the solids under a foot (check/). It is a container, not a
// decision: it knows nothing of what its items mean.
//
// Input: the cell size (mm). Cells are addressed by (floor(x / cell), floor(y / cell)); empty
// cells take no memory. Rings are visited in a fixed order (i, then j, ascending), so a search
// that stops early finds the same items on every run.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <deque>
#include <type_traits>
#include <vector>

#include "core/flat_index.hpp"
#include "core/geometry.hpp"

namespace cs {

template <typename T>
class XyGrid {
public:
    explicit XyGrid(double cell) : cell_(cell) {}

    double cell() const { return cell_; }
    // The index of the cell column (or row) that coordinate v falls in.
    long index(double v) const { return static_cast<long>(std::floor(v / cell_)); }

    void insert(const Vec3& p, T item) { insert_at(index(p.x), index(p.y), std::move(item)); }
    void insert_at(long i, long j, T item) { cell(key(i, j)).push_back(std::move(item)); }
    // Removes the first item equal to `item` from p's cell (which must hold it).
    void erase(const Vec3& p, const T& item) {
        auto& v = cell(key(index(p.x), index(p.y)));
        v.erase(std::find(v.begin(), v.end(), item));
    }

    // The items of cell (i, j), or null where it is empty.
    const std::vector<T>* at(long i, long j) const { return find(key(i, j)); }

    // Calls visit(item) for every item in the cells k rings around p's cell (k = 0: that cell;
    // k = 1: the eight around it; ...). When visit returns bool, true stops the visit; the
    // function then returns true.
    template <typename Visit>
    bool visit_ring(const Vec3& p, long k, Visit visit) const {
        const long ci = index(p.x), cj = index(p.y);
        auto visit_cell = [&](long i, long j) {
            const std::vector<T>* items = find(key(i, j));
            if (!items) return false;
            for (const T& item : *items) {
                if constexpr (std::is_same_v<decltype(visit(item)), bool>) {
                    if (visit(item)) return true;
                } else {
                    visit(item);
                }
            }
            return false;
        };
        // The ring's cells by i, then j, ascending: whole columns at its two ends, two cells between.
        for (long i = ci - k; i <= ci + k; ++i) {
            if (i == ci - k || i == ci + k) {
                for (long j = cj - k; j <= cj + k; ++j)
                    if (visit_cell(i, j)) return true;
            } else if (visit_cell(i, cj - k) || visit_cell(i, cj + k)) {
                return true;
            }
        }
        return false;
    }

    // Rings 0 to `rings` around p's cell, nearest first; same stopping rule as visit_ring.
    template <typename Visit>
    bool visit_near(const Vec3& p, long rings, Visit visit) const {
        for (long k = 0; k <= rings; ++k)
            if (visit_ring(p, k, visit)) return true;
        return false;
    }

private:
    static std::uint64_t key(long i, long j) { return (std::uint64_t(i) << 32) ^ std::uint64_t(j & 0xffffffff); }

    // The cells' item lists, found by key through a FlatIndex: a search asks for many empty cells,
    // each one probe.
    static std::uint64_t hash(std::uint64_t k) {
        k ^= k >> 33, k *= 0xff51afd7ed558ccdull, k ^= k >> 33;  // murmur3's finaliser
        return k;
    }
    const std::vector<T>* find(std::uint64_t k) const {
        const std::size_t at = index_.find(hash(k), [&](std::size_t i) { return keys_[i] == k; });
        return at == FlatIndex::npos ? nullptr : &lists_[at];
    }
    std::vector<T>& cell(std::uint64_t k) {
        const auto [at, fresh] = index_.insert(
            hash(k), lists_.size(), [&](std::size_t i) { return keys_[i] == k; }, [&](std::size_t i) { return hash(keys_[i]); });
        if (fresh) lists_.emplace_back(), keys_.push_back(k);
        return lists_[at];
    }

    double cell_;
    std::deque<std::vector<T>> lists_;  // a deque: a list stays where it is as cells are added
    std::vector<std::uint64_t> keys_;   // each list's cell
    FlatIndex index_;
};

}  // namespace cs
