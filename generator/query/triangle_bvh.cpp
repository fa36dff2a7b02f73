#include "query/triangle_bvh.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace cs {
namespace {

constexpr std::uint32_t kLeafSize = 4;

// Widened outwards by a relative 1e-9 (and 1e-9 absolute near 0): no rounding of a test can then
// miss a triangle that touches the question.
double below(double v) { return v - 1e-9 * (1 + std::abs(v)); }
double above(double v) { return v + 1e-9 * (1 + std::abs(v)); }

}  // namespace

TriangleBvh::TriangleBvh(const Mesh& mesh) {
    const std::size_t n = mesh.faces.size();
    if (n == 0) return;
    std::vector<Box> face_box(n);
    std::vector<Vec3> centre(n);
    for (std::size_t f = 0; f < n; ++f) {
        Box& b = face_box[f];
        for (int k = 0; k < 3; ++k) b.lo[k] = INFINITY, b.hi[k] = -INFINITY;
        for (int i = 0; i < 3; ++i) {
            const Vec3& v = mesh.vertices[mesh.faces[f][i]];
            const double c[3] = {v.x, v.y, v.z};
            for (int k = 0; k < 3; ++k) b.lo[k] = std::min(b.lo[k], c[k]), b.hi[k] = std::max(b.hi[k], c[k]);
        }
        for (int k = 0; k < 3; ++k) b.lo[k] = below(b.lo[k]), b.hi[k] = above(b.hi[k]);
        centre[f] = {(b.lo[0] + b.hi[0]) / 2, (b.lo[1] + b.hi[1]) / 2, (b.lo[2] + b.hi[2]) / 2};
    }
    faces_.resize(n);
    std::iota(faces_.begin(), faces_.end(), 0u);
    nodes_.reserve(2 * (n / kLeafSize + 1));

    // Top-down: each node's faces split at the median of their centres along the box's longest
    // side (balanced by count, so the depth stays about log2(n / 4) and the stacks small). A
    // node's first child is the next node, its second follows the first's whole subtree.
    auto build = [&](auto&& self, std::uint32_t begin, std::uint32_t end) -> void {
        const std::uint32_t at = static_cast<std::uint32_t>(nodes_.size());
        nodes_.push_back({});
        Box box;
        for (int k = 0; k < 3; ++k) box.lo[k] = INFINITY, box.hi[k] = -INFINITY;
        for (std::uint32_t i = begin; i < end; ++i) {
            const Box& b = face_box[faces_[i]];
            for (int k = 0; k < 3; ++k) box.lo[k] = std::min(box.lo[k], b.lo[k]), box.hi[k] = std::max(box.hi[k], b.hi[k]);
        }
        nodes_[at].box = box;
        if (end - begin <= kLeafSize) {
            nodes_[at].first = begin;
            nodes_[at].count = end - begin;
            return;
        }
        int axis = 0;
        for (int k = 1; k < 3; ++k)
            if (box.hi[k] - box.lo[k] > box.hi[axis] - box.lo[axis]) axis = k;
        auto coord = [&](std::uint32_t f) { return axis == 0 ? centre[f].x : axis == 1 ? centre[f].y : centre[f].z; };
        const std::uint32_t mid = begin + (end - begin) / 2;
        std::nth_element(faces_.begin() + begin, faces_.begin() + mid, faces_.begin() + end,
                         [&](std::uint32_t a, std::uint32_t b) { return coord(a) < coord(b) || (coord(a) == coord(b) && a < b); });
        self(self, begin, mid);
        nodes_[at].first = static_cast<std::uint32_t>(nodes_.size());
        self(self, mid, end);
    };
    build(build, 0, static_cast<std::uint32_t>(n));
    boxes_.resize(n);
    for (std::size_t s = 0; s < n; ++s) boxes_[s] = face_box[faces_[s]];
}

}  // namespace cs
