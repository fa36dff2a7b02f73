#include "query/triangle_bvh.hpp"

#include <algorithm>
#include <cmath>

namespace cs {
namespace {

constexpr std::uint32_t kLeafSize = 4;

// Widened outwards by a relative 1e-9 (and 1e-9 absolute near 0): no rounding of a test can then
// miss a triangle that touches the question.
double below(double v) { return v - 1e-9 * (1 + std::abs(v)); }
double above(double v) { return v + 1e-9 * (1 + std::abs(v)); }

}  // namespace

namespace {

// A face while the hierarchy is built: its widened box, kept together so each level's pass over a
// node's faces reads memory in order. Its centre is worked out where it is needed, not stored:
// each level's passes read every item of the model, so a smaller one (56 bytes, not 80) is read
// sooner; the centre is the same value either way.
struct Item {
    double lo[3], hi[3];
    std::uint32_t face;
    double centre(int k) const { return (lo[k] + hi[k]) / 2; }
};

}  // namespace

TriangleBvh::TriangleBvh(const Mesh& mesh) {
    const std::size_t n = mesh.faces.size();
    if (n == 0) return;
    const Box empty{{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
    auto grow = [](Box& into, const double* lo, const double* hi) {
        for (int k = 0; k < 3; ++k) into.lo[k] = std::min(into.lo[k], lo[k]), into.hi[k] = std::max(into.hi[k], hi[k]);
    };
    auto area = [](const Box& b) {
        const double dx = b.hi[0] - b.lo[0], dy = b.hi[1] - b.lo[1], dz = b.hi[2] - b.lo[2];
        return dx * dy + dy * dz + dz * dx;
    };
    std::vector<Item> items(n);
    Box box = empty, centres = empty;
    for (std::size_t f = 0; f < n; ++f) {
        Item& it = items[f];
        it.face = static_cast<std::uint32_t>(f);
        for (int k = 0; k < 3; ++k) it.lo[k] = INFINITY, it.hi[k] = -INFINITY;
        for (int i = 0; i < 3; ++i) {
            const Vec3& v = mesh.vertices[mesh.faces[f][i]];
            const double c[3] = {v.x, v.y, v.z};
            for (int k = 0; k < 3; ++k) it.lo[k] = std::min(it.lo[k], c[k]), it.hi[k] = std::max(it.hi[k], c[k]);
        }
        for (int k = 0; k < 3; ++k) it.lo[k] = below(it.lo[k]), it.hi[k] = above(it.hi[k]);
        const double centre[3] = {it.centre(0), it.centre(1), it.centre(2)};
        grow(box, it.lo, it.hi);
        grow(centres, centre, centre);
    }
    nodes_.reserve(2 * (n / kLeafSize + 1));

    // Top-down: each node's faces are binned (12 bins) along the longest side of their centres'
    // box and cut between two bins where the surface-area heuristic expects the fewest box and
    // face tests; one pass per level, the children's boxes come from the bins. A node's first
    // child is the next node, its second follows the first's whole subtree. Past depth 40 (never
    // on the benchmark's models) or where all centres coincide, a node is halved by count, so
    // the traversal stacks (128) cannot overflow.
    constexpr int kBins = 12;
    struct Bin {
        Box box, centres;
        std::uint32_t count = 0;
    };
    auto build = [&](auto&& self, std::uint32_t begin, std::uint32_t end, const Box& box, const Box& centres,
                     int depth) -> void {
        const std::uint32_t at = static_cast<std::uint32_t>(nodes_.size());
        nodes_.push_back({});
        nodes_[at].box = box;
        if (end - begin <= kLeafSize) {
            nodes_[at].first = begin;
            nodes_[at].count = end - begin;
            return;
        }
        int axis = 0;
        for (int k = 1; k < 3; ++k)
            if (centres.hi[k] - centres.lo[k] > centres.hi[axis] - centres.lo[axis]) axis = k;
        const double lo = centres.lo[axis], extent = centres.hi[axis] - lo;
        std::uint32_t mid;
        Box halves[2] = {empty, empty}, half_centres[2] = {empty, empty};
        if (extent > 0 && depth < 40) {
            const double scale = kBins / extent;
            auto bin_of = [&](const Item& it) { return std::min(kBins - 1, static_cast<int>((it.centre(axis) - lo) * scale)); };
            Bin bins[kBins];
            for (auto& b : bins) b.box = b.centres = empty;
            for (std::uint32_t i = begin; i < end; ++i) {
                Bin& b = bins[bin_of(items[i])];
                const double centre[3] = {items[i].centre(0), items[i].centre(1), items[i].centre(2)};
                grow(b.box, items[i].lo, items[i].hi);
                grow(b.centres, centre, centre);
                ++b.count;
            }
            double right_area[kBins] = {};
            std::uint32_t right_count[kBins] = {};
            Box r = empty;
            std::uint32_t rc = 0;
            for (int j = kBins - 1; j > 0; --j) {
                grow(r, bins[j].box.lo, bins[j].box.hi), rc += bins[j].count;
                right_area[j] = area(r), right_count[j] = rc;
            }
            Box l = empty;
            std::uint32_t lc = 0;
            int cut = 1;
            double best = INFINITY;
            for (int j = 1; j < kBins; ++j) {  // cut between bins j - 1 and j
                grow(l, bins[j - 1].box.lo, bins[j - 1].box.hi), lc += bins[j - 1].count;
                if (lc == 0 || right_count[j] == 0) continue;
                const double cost = area(l) * lc + right_area[j] * right_count[j];
                if (cost < best) best = cost, cut = j;
            }
            for (int j = 0; j < kBins; ++j) {
                grow(halves[j >= cut], bins[j].box.lo, bins[j].box.hi);
                grow(half_centres[j >= cut], bins[j].centres.lo, bins[j].centres.hi);
            }
            mid = static_cast<std::uint32_t>(
                std::partition(items.begin() + begin, items.begin() + end, [&](const Item& it) { return bin_of(it) < cut; }) -
                items.begin());
        } else {
            mid = begin + (end - begin) / 2;
            std::nth_element(items.begin() + begin, items.begin() + mid, items.begin() + end,
                             [&](const Item& a, const Item& b) {
                                 return a.centre(axis) < b.centre(axis) || (a.centre(axis) == b.centre(axis) && a.face < b.face);
                             });
            for (std::uint32_t i = begin; i < end; ++i) {
                const double centre[3] = {items[i].centre(0), items[i].centre(1), items[i].centre(2)};
                grow(halves[i >= mid], items[i].lo, items[i].hi);
                grow(half_centres[i >= mid], centre, centre);
            }
        }
        self(self, begin, mid, halves[0], half_centres[0], depth + 1);
        nodes_[at].first = static_cast<std::uint32_t>(nodes_.size());
        self(self, mid, end, halves[1], half_centres[1], depth + 1);
    };
    build(build, 0, static_cast<std::uint32_t>(n), box, centres, 0);
    faces_.resize(n);
    boxes_.resize(n);
    for (std::size_t s = 0; s < n; ++s) {
        faces_[s] = items[s].face;
        for (int k = 0; k < 3; ++k) boxes_[s].lo[k] = items[s].lo[k], boxes_[s].hi[k] = items[s].hi[k];
    }
}

}  // namespace cs
