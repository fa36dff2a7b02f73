// core/xy_grid.hpp: the hash grid every "what is near, seen from above" question asks. Its cells
// are found through an open-addressed index (speed5; a std::unordered_map before): the items, the
// order they are visited in and where a visit stops must be those of a plain map of cells walked
// cell by cell.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "core/xy_grid.hpp"

namespace cs {
namespace {

// The reference: cells in a std::map, ring k walked over its whole square, i then j ascending,
// every cell not on the ring skipped.
struct PlainGrid {
    double cell;
    std::map<std::pair<long, long>, std::vector<int>> cells;
    long index(double v) const { return static_cast<long>(std::floor(v / cell)); }
    void insert(const Vec3& p, int item) { cells[{index(p.x), index(p.y)}].push_back(item); }
    void erase(const Vec3& p, int item) {
        auto& v = cells[{index(p.x), index(p.y)}];
        v.erase(std::find(v.begin(), v.end(), item));
    }
    // The items visited, rings 0 to `rings`, until `stop` (an item) is met.
    std::vector<int> visit_near(const Vec3& p, long rings, int stop) const {
        std::vector<int> seen;
        const long ci = index(p.x), cj = index(p.y);
        for (long k = 0; k <= rings; ++k)
            for (long i = ci - k; i <= ci + k; ++i)
                for (long j = cj - k; j <= cj + k; ++j) {
                    if (std::max(std::abs(i - ci), std::abs(j - cj)) != k) continue;
                    auto it = cells.find({i, j});
                    if (it == cells.end()) continue;
                    for (int item : it->second) {
                        seen.push_back(item);
                        if (item == stop) return seen;
                    }
                }
        return seen;
    }
};

TEST(XyGrid, VisitsTheItemsOfAPlainMapOfCellsInItsOrder) {
    std::mt19937 rng(32);
    std::uniform_real_distribution<double> u(-30, 30);
    XyGrid<int> grid(1.5);
    PlainGrid plain{1.5, {}};
    std::vector<Vec3> at;
    for (int item = 0; item < 3000; ++item) {  // clustered and spread: some cells hold many items
        const Vec3 p = item % 3 ? Vec3{u(rng), u(rng), 0} : Vec3{0.1 * u(rng), 0.1 * u(rng), 0};
        grid.insert(p, item), plain.insert(p, item), at.push_back(p);
    }
    for (int item = 0; item < 3000; item += 7) grid.erase(at[item], item), plain.erase(at[item], item);
    for (int q = 0; q < 300; ++q) {
        const Vec3 p{u(rng), u(rng), 0};
        const long rings = q % 6;
        const int stop = q % 2 ? -1 : static_cast<int>(rng() % 3000);  // a visit that stops early
        std::vector<int> seen;
        const bool stopped = grid.visit_near(p, rings, [&](int item) {
            seen.push_back(item);
            return item == stop;
        });
        const std::vector<int> expected = plain.visit_near(p, rings, stop);
        EXPECT_EQ(seen, expected) << q;
        EXPECT_EQ(stopped, !expected.empty() && expected.back() == stop) << q;
        const long i = plain.index(p.x), j = plain.index(p.y);
        const std::vector<int>* cell = grid.at(i, j);
        auto it = plain.cells.find({i, j});
        if (it == plain.cells.end()) {
            EXPECT_EQ(cell, nullptr);
        } else {
            ASSERT_NE(cell, nullptr);
            EXPECT_EQ(*cell, it->second);
        }
    }
}

// A cell's items stay where they are while other cells are added (as a node-based map's did).
TEST(XyGrid, ACellsItemsStayPutAsCellsAreAdded) {
    XyGrid<int> grid(1.0);
    grid.insert({0.5, 0.5, 0}, 1);
    const std::vector<int>* first = grid.at(0, 0);
    for (int k = 0; k < 5000; ++k) grid.insert({k * 1.0 + 10.5, -k * 2.0, 0}, k);
    EXPECT_EQ(grid.at(0, 0), first);
    EXPECT_EQ(*first, std::vector<int>{1});
}

}  // namespace
}  // namespace cs
