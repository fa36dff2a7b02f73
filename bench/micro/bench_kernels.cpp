// Microbenchmarks of the generator's hot kernels (bench/README.md):
//   BM_CollectContacts the cone-mesh query (collect_contacts: the cone fan's rays to the model and
//                      the bed) from the tip apexes of a real model's overhang samples: armadillo
//                      at benchmark scale (0.528751), or a procedural sphere when ../shared/models
//                      is absent;
//   BM_GrowTreeLattice grow_tree on a flat lattice of N samples (1.5 mm pitch) under a plate,
//                      N = 1k, 4k, 16k (the merge step: every leaf drops to the bed and merges);
//   BM_MergePoint      merge_point on random apex pairs.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "core/geometry.hpp"
#include "core/params.hpp"
#include "mesh/mesh_io.hpp"
#include "mesh/repair.hpp"
#include "overhang/overhang.hpp"
#include "query/model_query.hpp"
#include "tree/tree.hpp"

#ifndef CS_SHARED_MODELS
#define CS_SHARED_MODELS "../shared/models"
#endif

namespace {

using namespace cs;

// A closed UV sphere (outward faces), radius r, centred at c.
Mesh uv_sphere(double r, Vec3 c, int stacks = 64, int slices = 128) {
    Mesh m;
    m.vertices.push_back(c + Vec3{0, 0, -r});
    for (int i = 1; i < stacks; ++i) {
        double th = M_PI * i / stacks - M_PI / 2;
        for (int j = 0; j < slices; ++j) {
            double ph = 2 * M_PI * j / slices;
            m.vertices.push_back(c + Vec3{r * std::cos(th) * std::cos(ph), r * std::cos(th) * std::sin(ph), r * std::sin(th)});
        }
    }
    m.vertices.push_back(c + Vec3{0, 0, r});
    auto ring = [&](int i, int j) { return std::uint32_t(1 + (i - 1) * slices + (j % slices)); };
    std::uint32_t bottom = 0, top = std::uint32_t(m.vertices.size() - 1);
    for (int j = 0; j < slices; ++j) m.faces.push_back({bottom, ring(1, j + 1), ring(1, j)});
    for (int i = 1; i + 1 < stacks; ++i)
        for (int j = 0; j < slices; ++j) {
            m.faces.push_back({ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)});
            m.faces.push_back({ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)});
        }
    for (int j = 0; j < slices; ++j) m.faces.push_back({ring(stacks - 1, j), ring(stacks - 1, j + 1), top});
    return m;
}

// Axis-aligned closed box, outward faces.
Mesh box(Vec3 lo, Vec3 hi) {
    Mesh m;
    for (int i = 0; i < 8; ++i)
        m.vertices.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
    const Triangle f[12] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                            {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    m.faces.assign(f, f + 12);
    return m;
}

struct ConeFixture {
    std::string source;
    Mesh placed;
    std::unique_ptr<ModelQuery> query;
    std::vector<Vec3> apexes;
    Params params;

    ConeFixture() {
        const std::string path = std::string(CS_SHARED_MODELS) + "/armadillo.stl";
        Mesh raw;
        double scale = 1;
        if (std::filesystem::exists(path)) {
            raw = read_mesh(path);
            scale = 0.528751;  // benchmark.json
            source = "armadillo.stl x0.528751";
        } else {
            raw = uv_sphere(30, {0, 0, 30});
            source = "procedural sphere r=30";
        }
        RepairReport rr;
        Mesh repaired = repair_mesh(raw, source, rr);
        Placement pl;
        const double id[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
        placed = place_on_bed(repaired, scale, id, pl);
        query = std::make_unique<ModelQuery>(placed);
        const OverhangOptions oo = overhang_options(params);
        // Leaves hang one tip (plus the gap) below each overhang sample: query from there.
        for (const auto& s : sample_overhangs(placed, oo).samples) {
            Vec3 a = s.p - Vec3{0, 0, params.gap + params.tip_length};
            if (a.z > 0.5) apexes.push_back(a);
        }
    }
};

ConeFixture& cone_fixture() {
    static ConeFixture f;
    return f;
}

void BM_CollectContacts(benchmark::State& state) {
    auto& f = cone_fixture();
    const ConeFan fan(f.params.critical_angle);
    const CandidateContext cx{*f.query, f.params, fan, true};
    std::size_t i = 0, hits = 0;
    std::vector<Candidate> found;
    for (auto _ : state) {
        found.clear();
        collect_contacts(cx, f.apexes[i], INFINITY, nullptr, nullptr, found);
        hits += std::any_of(found.begin(), found.end(), [](const Candidate& c) { return c.type != Target::Bed; });
        benchmark::DoNotOptimize(found.data());
        if (++i == f.apexes.size()) i = 0;
    }
    state.SetItemsProcessed(state.iterations());
    state.SetLabel(f.source + ", " + std::to_string(f.apexes.size()) + " apexes, " +
                   std::to_string(f.placed.faces.size()) + " tris");
    state.counters["hit_fraction"] = state.iterations() ? double(hits) / double(state.iterations()) : 0;
}
BENCHMARK(BM_CollectContacts);

// N samples on a square lattice (pitch = sampling distance) on the underside of a plate at z = h.
void BM_GrowTreeLattice(benchmark::State& state) {
    const int side = int(std::lround(std::sqrt(double(state.range(0)))));
    Params p;
    const double pitch = p.sampling_distance, h = 20.0;
    const double half = 0.5 * pitch * (side - 1);
    Mesh plate = box({-half - 2, -half - 2, h}, {half + 2, half + 2, h + 2});
    ModelQuery q(plate);
    std::vector<Sample> samples;
    for (int i = 0; i < side; ++i)
        for (int j = 0; j < side; ++j) samples.push_back({{-half + i * pitch, -half + j * pitch, h}, SampleKind::Face});
    std::sort(samples.begin(), samples.end(), [](const Sample& a, const Sample& b) {
        if (a.p.z != b.p.z) return a.p.z > b.p.z;
        if (a.p.x != b.p.x) return a.p.x < b.p.x;
        return a.p.y < b.p.y;
    });
    std::size_t struts = 0, merges = 0;
    for (auto _ : state) {
        SupportTree t = grow_tree(q, samples, p);
        struts = t.struts.size();
        merges = t.stats.merges;
        benchmark::DoNotOptimize(t);
    }
    state.SetItemsProcessed(state.iterations() * std::int64_t(samples.size()));
    state.SetComplexityN(std::int64_t(samples.size()));
    state.counters["samples"] = double(samples.size());
    state.counters["struts"] = double(struts);
    state.counters["merges"] = double(merges);
}
BENCHMARK(BM_GrowTreeLattice)->Arg(1024)->Arg(4096)->Arg(16384)->Unit(benchmark::kMillisecond)->Complexity(benchmark::oNLogN);

void BM_MergePoint(benchmark::State& state) {
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> xy(-20, 20), z(1, 60);
    std::vector<std::pair<Vec3, Vec3>> pairs(4096);
    for (auto& [a, b] : pairs) {
        a = {xy(rng), xy(rng), z(rng)};
        b = {xy(rng), xy(rng), z(rng)};
        if (a.z < b.z) std::swap(a, b);
    }
    const double tan_c = std::tan(50.0 * M_PI / 180.0);
    std::size_t i = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(merge_point(pairs[i].first, pairs[i].second, tan_c));
        i = (i + 1) & 4095;
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_MergePoint);

}  // namespace

BENCHMARK_MAIN();
