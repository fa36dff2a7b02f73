// Where a node of the sweep could go next: its candidates (docs/algorithm.md section 3).
//
// A node at `a` may end its strut
//   - on the model or the bed, along one direction of the cone fan (collect_contacts), or
//   - where its cone meets another active node's (collect_merges, merge_point).
// Each candidate says how far down the node stays an island of its own (`span`: what a slicer
// pays for) and how long its strut is; by_cost ranks them. Whether a candidate's strut is clear of
// the model is not asked here (tree/clearance.hpp), nor which one is taken (the sweep, tree.cpp).
#pragma once

#include <cstddef>
#include <optional>
#include <unordered_map>
#include <vector>

#include "core/geometry.hpp"
#include "core/params.hpp"
#include "core/xy_grid.hpp"

namespace cs {

class ModelQuery;
struct Node;

// Highest point where the downward cones of apexes a and b meet (docs/algorithm.md section 3):
// b itself when it lies in a's cone, else the top of the cones' intersection. a must not be lower
// than b. tan_c = tan(critical angle).
Vec3 merge_point(const Vec3& a, const Vec3& b, double tan_c);

// Unit directions of the cone fan: the axis, then the rings of kTreeTuning (tree/tuning.hpp).
std::vector<Vec3> cone_fan(double critical_angle_deg);

// The cone fan with what the sweep asks of it: masks of its vertical and slanted directions and
// the cosine of its steepest slant.
struct ConeFan {
    std::vector<Vec3> dirs;
    std::vector<char> vertical_only, slanted_only;  // masks over dirs
    double cos_min = 1;                             // cosine of the fan's steepest slant
    double tan_c = 0;                               // tan(critical angle)

    explicit ConeFan(double critical_angle_deg);
};

// SteepModel: a model point too steep to stand on, used only when nothing else fits.
enum class Target { InCone, Merge, Model, Bed, SteepModel };

struct Candidate {
    double dist;      // strut length
    Target type;
    double span = 0;  // how far down the node stays an island of its own: what a slicer pays for
    int other = -1;   // the partner node of a merge
    Vec3 point;       // merge point, contact node, or bed point
    Vec3 contact;     // model point below a contact node
};

// What every candidate search reads: the model, the user's parameters, the fan, and whether
// slanted struts and merges are allowed (the tree) or not (the columns baseline).
struct CandidateContext {
    const ModelQuery& model;
    const Params& p;
    const ConeFan& fan;
    bool tree;
};

// Model and bed candidates of a node at `a` along the fan directions marked in `only` (all when
// null). With a finite `reach`, slanted rays are first asked whether the model is within that
// reach at all (a cheap segment test); the directions passed over are marked in `skipped` for a
// second pass should nothing near be clear.
void collect_contacts(const CandidateContext& cx, const Vec3& a, double reach, std::vector<char>* skipped,
                      const std::vector<char>* only, std::vector<Candidate>& out);

// The sweep's active nodes: an XY grid for "the other active points near this one", and a list
// of them all for when the rings outgrow the population.
class ActiveNodes {
public:
    explicit ActiveNodes(double cell) : grid_(cell) {}

    void insert(int id, const Vec3& p);
    void remove(int id, const Vec3& p);
    std::size_t size() const { return list_.size(); }

    // Calls visit(id) for active nodes in rings of cells around p until stop(ring_distance) says
    // that nothing farther can matter; falls back to all nodes when rings outgrow the population.
    template <typename Visit, typename Stop>
    void visit_near(const Vec3& p, Visit visit, Stop stop) const {
        for (long k = 0;; ++k) {
            if ((2 * k + 1) * (2 * k + 1) > 4 * static_cast<long>(list_.size()) + 64) {
                for (int id : list_) visit(id);
                return;
            }
            grid_.visit_ring(p, k, visit);
            if (stop(k * grid_.cell())) return;
        }
    }

private:
    XyGrid<int> grid_;
    std::unordered_map<int, std::size_t> pos_;
    std::vector<int> list_;
};

// Merge candidates of node `id`: where its cone meets those of active nodes the sweep has not
// passed (but those in `banned`), the `keep` cheapest (cost_less) with a span below `bound` that
// come after `after` (all from the cheapest when null). Fetching batch after batch, each after
// the last one's dearest, lists every merge in cost order.
void collect_merges(const CandidateContext& cx, const ActiveNodes& active, const std::vector<Node>& nodes, int id,
                    const std::vector<int>& banned, double bound, const Candidate* after, std::size_t keep,
                    std::vector<Candidate>& out);

// Cheapest for the slicer first: the fewest layers the node stays an island of its own, so
// branches join as high as they can and trunks carry them down; then the shorter strut.
bool cost_less(const Candidate& x, const Candidate& y);
void by_cost(std::vector<Candidate>& c);

}  // namespace cs
