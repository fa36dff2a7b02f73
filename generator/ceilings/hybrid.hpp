// The hybrid under ceilings high over the model (issue #32, "a hybrid like Bambu's"): where walls
// cannot stand on the bed or a level floor (ceilings/ceilings.hpp), short walls `hybrid_height`
// tall hang just under the ceiling in the same rows and meander, and the tree carries them: a tip
// stands under the middle of each piece's foot. The slicer then prints the top layers under the
// ceiling as a few long lines (where a tree prints one island per tip), and the tree below grows
// from fewer leaves (one per piece, pieces ceiling_span apart in rows ceiling_span apart, where
// the sampling hangs one per sampling distance).
//
// Stage: ceilings (after the walls, on the samples they leave). The tree stage hangs the feet as
// leaves (tree/feet.hpp); where the tree loses some of them, the pipeline drops those feet's pieces
// (without_feet) and grows the tree again, keeping what is left where the time model still
// prefers it to no hybrid.
//
//   support_hybrid(model, samples, p, tree_count, blockers) -> Ceilings{walls, rest, feet, ...}
//     regions, rows, joins, tops  as for walls (lay_out_ceilings), the floor of every station
//               `hybrid_height` under its top, where the fall below leaves room for a tip and a
//               strut (hybrid_floor)
//     pieces    each flat piece cut into as few pieces as the printer bridges (hybrid_piece_cuts),
//               each at least as long as `check` still finds a long top (a contact along it), each
//               standing on one tip at the middle of its foot: `check` grounds a solid by its
//               foot's middle. A row's end pieces under twice a long top (under 7.5 mm at the
//               default sampling: each overhangs its foot by under a long top), the pieces between
//               them up to p.hybrid_bridge (the printer bridges the row's bottom from tip to tip).
//               Fewer pieces, fewer feet: each is a tip of the tree
//     feet      a piece whose tip does not fit (the model too near) is not built
//     choice    per region by core/slicer_time: the pieces' lines over their height plus the tree
//               for the samples they leave and their feet, against the region's own tree, on
//               both routes; then in the whole, one priced region at a time: its choice flips
//               where the taken regions' lines plus the one tree for every sample they leave,
//               with all their feet, is then faster on both routes (a region's feet merge with
//               its neighbours' leaves: alone, the wheel at 80 mm priced a region's hybrid 15 %
//               dearer on Cura, and the whole 2 % cheaper with it)
//
// Example: a 30 x 10 mm roof 20 mm over a slope, hybrid_height 3, span 3.4: 4 rows of 3 mm walls
// under it, each row cut into 5 pieces 6 mm long, with the 3 joins 23 feet; the tree grows from
// those instead of ~48 samples.
#pragma once

#include <functional>
#include <optional>
#include <vector>

#include "ceilings/ceilings.hpp"

namespace cs {

// The tree for some samples plus a tip under each foot (counted as TreeCounter counts it).
using FeetTreeCounter = std::function<TreeCount(const std::vector<Sample>&, const std::vector<Vec3>& feet)>;

// The hybrid on `samples` (those the walls left), none entering `support_blockers` (the user's,
// and the walls' own boxes). Nothing when p.hybrid_height is 0. `rows_across` as for
// lay_out_ceilings; off where the hybrid is priced as the walls' rival (pipeline): priced alone,
// rows across enclosure_lid's ears made the hybrid look cheaper than the walls there on both
// routes, and the whole (the tree under its feet) printed slower (PrusaSlicer +0.7 min).
Ceilings support_hybrid(const ModelQuery& model, const std::vector<Sample>& samples, const Params& p,
                        const FeetTreeCounter& tree_count, const std::vector<Box3>& support_blockers = {},
                        const TipAt& tip_at = {}, const std::vector<char>& stay = {}, bool rows_across = true);

// Where a hybrid row's flat piece `length` long is cut into pieces, as fractions of it from 0 to 1
// (increasing, first 0, last 1): the fewest pieces whose two end pieces are shorter than `end_most`
// and whose pieces between them are at most `bridge` long and no shorter than the ends. Where
// `bridge` is no longer than `end_most` (p.hybrid_bridge 0, as before it was a parameter), equal
// pieces each shorter than `end_most`; so too where the rule would stand as many feet as they do
// (their bridges are the shorter).
// Example: hybrid_piece_cuts(40, 7.8, 10): 5 pieces, the ends 6.84 mm, the three between 8.77 mm
// (equal pieces under 7.8 mm would be 6).
std::vector<double> hybrid_piece_cuts(double length, double end_most, double bridge);

// Under a point `x` of a ceiling: the foot of a hybrid wall, hybrid_height and a gap below it,
// where the model (or the bed) below leaves room under the foot for a tip and a strut to leave
// it; else nothing.
std::optional<double> hybrid_floor(const ModelQuery& model, const Vec3& x, const Params& p);

// The hybrid `h` (support_hybrid on `samples`, `stay` per sample) without the pieces whose feet are
// among `lost`: the samples only those pieces carried go back to the tree (carried_by).
// Example: a tree that could not reach 1 of 17 feet (the molecule example, kept pose) keeps 16.
Ceilings without_feet(const ModelQuery& model, const std::vector<Sample>& samples, const std::vector<char>& stay,
                      const Ceilings& h, const std::vector<Vec3>& lost, const Params& p);

// Where the tip under each piece stands: the middle of its foot.
std::vector<Vec3> feet_of(const std::vector<CeilingWall>& pieces);

}  // namespace cs
