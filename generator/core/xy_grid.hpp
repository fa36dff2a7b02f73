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
#include <type_traits>
#include <unordered_map>
#include <vector>

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
    void insert_at(long i, long j, T item) { cells_[key(i, j)].push_back(std::move(item)); }
    // Removes the first item equal to `item` from p's cell (which must hold it).
    void erase(const Vec3& p, const T& item) {
        auto& v = cells_[key(index(p.x), index(p.y))];
        v.erase(std::find(v.begin(), v.end(), item));
    }

    // The items of cell (i, j), or null where it is empty.
    const std::vector<T>* at(long i, long j) const {
        auto it = cells_.find(key(i, j));
        return it == cells_.end() ? nullptr : &it->second;
    }

    // Calls visit(item) for every item in the cells k rings around p's cell (k = 0: that cell;
    // k = 1: the eight around it; ...). When visit returns bool, true stops the visit; the
    // function then returns true.
    template <typename Visit>
    bool visit_ring(const Vec3& p, long k, Visit visit) const {
        const long ci = index(p.x), cj = index(p.y);
        for (long i = ci - k; i <= ci + k; ++i)
            for (long j = cj - k; j <= cj + k; ++j) {
                if (std::max(std::abs(i - ci), std::abs(j - cj)) != k) continue;
                auto it = cells_.find(key(i, j));
                if (it == cells_.end()) continue;
                for (const T& item : it->second) {
                    if constexpr (std::is_same_v<decltype(visit(item)), bool>) {
                        if (visit(item)) return true;
                    } else {
                        visit(item);
                    }
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

    double cell_;
    std::unordered_map<std::uint64_t, std::vector<T>> cells_;
};

}  // namespace cs
