#include "mesh/weld.hpp"

#include <algorithm>
#include <array>
#include <bit>

namespace cs {
namespace {

// A vertex's coordinates as one 64-bit number: equal coordinates (-0 and +0 equal) give equal
// numbers. splitmix64's mixing over each coordinate's bits, +0 for -0.
std::uint64_t coordinate_hash(const Vec3& v) {
    std::uint64_t h = 0x9e3779b97f4a7c15ull;
    for (double d : {v.x, v.y, v.z}) {
        std::uint64_t z = h ^ std::bit_cast<std::uint64_t>(d + 0.0);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        h = z ^ (z >> 31);
    }
    return h;
}

struct Hashed {
    std::uint64_t h;
    std::uint32_t i;
};

// Sorted by hash, equal hashes in index order: a stable radix sort (11 bits a pass), or
// std::sort on (hash, index) for a few vertices.
void sort_by_hash(std::vector<Hashed>& a) {
    if (a.size() < 1024) {
        std::sort(a.begin(), a.end(), [](const Hashed& x, const Hashed& y) { return x.h != y.h ? x.h < y.h : x.i < y.i; });
        return;
    }
    constexpr int kBits = 11;
    constexpr std::size_t kBuckets = std::size_t{1} << kBits;
    std::vector<Hashed> b(a.size());
    for (int shift = 0; shift < 64; shift += kBits) {
        std::array<std::size_t, kBuckets> start{};
        for (const Hashed& x : a) ++start[(x.h >> shift) & (kBuckets - 1)];
        std::size_t sum = 0;
        for (std::size_t& s : start) {
            const std::size_t c = s;
            s = sum, sum += c;
        }
        for (const Hashed& x : a) b[start[(x.h >> shift) & (kBuckets - 1)]++] = x;
        a.swap(b);
    }
}

}  // namespace

Welded weld_vertices(const Mesh& m) {
    const auto& mv = m.vertices;
    const auto n = static_cast<std::uint32_t>(mv.size());
    // Vertices with equal coordinates have equal hashes: sorted by hash (equal hashes in index
    // order), each run of equal hashes holds whole classes of equal vertices, its first entry the
    // lowest index of its class unless two coordinates share a hash (then the run is split by
    // comparing them). Streaming passes over 16-byte entries, not a comparison sort of the
    // coordinates: a 5M-triangle scan has 15M vertices.
    std::vector<Hashed> sorted(n);
    for (std::uint32_t i = 0; i < n; ++i) sorted[i] = {coordinate_hash(mv[i]), i};
    sort_by_hash(sorted);
    // Each vertex -> the first vertex with its coordinates (the lowest index of its class).
    std::vector<std::uint32_t> first(n);
    for (std::size_t run = 0, next = 0; run < n; run = next) {
        next = run + 1;
        while (next < n && sorted[next].h == sorted[run].h) ++next;
        const Vec3& p = mv[sorted[run].i];
        bool one_class = true;
        for (std::size_t k = run; k < next; ++k) {
            const Vec3& q = mv[sorted[k].i];
            one_class = one_class && q.x == p.x && q.y == p.y && q.z == p.z;
            first[sorted[k].i] = sorted[run].i;
        }
        if (one_class) continue;
        // Different coordinates, one hash: each to the lowest earlier index with its coordinates.
        for (std::size_t k = run; k < next; ++k) {
            const Vec3& q = mv[sorted[k].i];
            for (std::size_t j = run; j <= k; ++j) {
                const Vec3& r = mv[sorted[j].i];
                if (q.x == r.x && q.y == r.y && q.z == r.z) {
                    first[sorted[k].i] = sorted[j].i;
                    break;
                }
            }
        }
    }
    sorted = {};
    Welded w;
    w.remap.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) {
        if (first[i] == i) {
            w.remap[i] = static_cast<std::uint32_t>(w.mesh.vertices.size());
            w.mesh.vertices.push_back(mv[i]);
        } else {
            w.remap[i] = w.remap[first[i]];  // first[i] < i: already numbered
        }
    }
    w.mesh.faces.reserve(m.faces.size());
    for (const auto& f : m.faces) w.mesh.faces.push_back({w.remap[f[0]], w.remap[f[1]], w.remap[f[2]]});
    return w;
}

}  // namespace cs
