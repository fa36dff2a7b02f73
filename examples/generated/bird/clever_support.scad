// clever_support.scad: the OpenSCAD side of clever-support .
//
// A generated <name>.scad file holds the support tree as DATA (nodes, struts [top, bottom], leaves,
// contact tips, beds, pillars) and `include`s this library, which holds the GEOMETRY as code:
// which struts carry which, the unbranched runs, and every strut's widths are derived here from
// the data and the parameters, so changing k, d_min, d_max, wall, the tips or the feet in the
// Customizer (or with `openscad -D k=0.003`), moving a node or adding a strut by hand re-sizes the
// whole tree consistently. This file must parse on OpenSCAD 2021.01 and 2025: no recursion deeper
// than a handful of calls, no hull(), one polyhedron per solid.
//
// Units: millimetres and degrees. +Z is up, the bed is z = 0.
//
// Width rules (the same as the C++ generator's struts stage):
//   eqn1      d = k * l * alpha, clamped to [d_min, d_max]      (paper Eqn 1; alpha from vertical)
//   strength  d >= sqrt(run_length / (strength_length * f(alpha))), f = 1 up to 30 deg, then -15%
//             per 20 deg: the paper's Table 1 (1 mm safe to 30 mm, 1.5 mm to 60 mm at 50 deg)
//   run       an unbranched chain of struts through bends (one strut in, one out, not a leaf):
//             its length is the sum, its angle the steepest
//   node      leaf: d_min; one strut in: its lower width; several: (sum w^3)^(1/3), at least the widest
//   strut     upper = clamp(max(node width, strength)), lower = max(upper, eqn1): never narrowing down
//   min_n     the narrowest N-profile: three walls (cs_min_n_width; narrower struts are solid squares)
//
// Modules
//   cs_prism(bottom, top, w_bottom, w_top, n_profile, wall)
//       one solid between two horizontal squares centred at `bottom` and `top` (points [x,y,z]),
//       side widths w_bottom / w_top (mm); filled with the N-profile (three walls `wall` thick)
//       when n_profile is true, else solid. Struts, tips, feet and pillars are all cs_prism.
//   cs_strut(a, b, w_a, w_b, wall, min_n)
//       an N-profile strut from upper point a to lower point b; solid square when narrower than min_n.
//   cs_tip(bottom, top, w_bottom, tip_diameter, wall)
//       a detachable tip: one taper from its strut (w_bottom, at `bottom`) to tip_diameter at `top`.
//   cs_contact_tip(bottom, top, tip_diameter, w_top, wall)
//       the same, upside down, where a strut stands on the model.
//   cs_foot(bed_point, toward, w, foot_height, foot_extra, room, clearance, wall)
//       a foot on the bed, w + 2*extra wide at z = 0, narrowing to w at foot_height along the strut;
//       extra = foot_extra unless the model is nearer than that (room: distance to the model).
//   cs_tree(tree, omit, highlight, k, d_min, d_max, strength_length, wall, tip_length, tip_diameter,
//           feet, foot_height, foot_extra, clearance)
//       the whole support from a generated tree record (`cs_tree_record` in generated files):
//       [nodes, struts, leaves, contacts, beds, pillars, overlap]
//         nodes    [[x,y,z], ...]
//         struts   [[top node, bottom node], ...]  (top above bottom)
//         leaves   [[node, [x,y,z] overhang sample, [x,y,z] tip top], ...]: the tip ends at its top, a
//                  gap below the sample (more under a slope, up to half a millimetre aside)
//         contacts [[node, [x,y,z] tip bottom], ...]: an upside-down tip from there up to the node
//         beds     [[node, room], ...]: nodes on the bed; room: distance from the foot to the model
//         pillars  [[[x,y,z] top, [x,y,z] bottom], ...]  too short for a tree: d_min up to the tip
//         overlap  how far a strut reaches into the solid below it (mm)
//       tip_length: how long the tips are is fixed by where the tree put its leaves and contact
//       nodes (a regrow parameter); cs_tree takes it only so files written before still call it.
//       omit: strut indices left out with every strut above them (their branch), and pillars
//       (pillar i is index len(struts) + i); highlight: a
//       strut index drawn red (-1: none).
//   cs_walls(walls, tree, omit)
//       the walls under ceilings (cs_walls in generated files), without the hybrid pieces standing
//       on the tips that `omit` takes out of the tree record `tree`.
//   cs_show_edits(blockers, points): see-through boxes and points in the preview (not rendered).
//   cs_strut_widths(...) returns [[upper, lower], ...] per strut, for inspection with echo().

// Node kinds, as the comments in a generated file name them. A dropped node (given up: no strut
// fits from there) stays in the data so indices do not move; nothing is built at it.
CS_LEAF = 0; CS_MERGE = 1; CS_BEND = 2; CS_BED = 3; CS_CONTACT = 4; CS_DROPPED = 5;

// ----------------------------------------------------------------------------- width rules

function cs_clamp(x, lo, hi) = min(max(x, lo), hi);
function cs_angle_factor(a) = max(0.3, 1 - 0.15 * max(0, a - 30) / 20);
function cs_strength_width(run_length, run_angle, strength_length) =
    sqrt(max(0, run_length) / (strength_length * cs_angle_factor(run_angle)));
function cs_eqn1(k, l, alpha, d_min, d_max) = cs_clamp(k * l * alpha, d_min, d_max);
function cs_cube_sum(ws) = [for (i = 0, s = 0; i <= len(ws); s = i < len(ws) ? s + pow(ws[i], 3) : s, i = i + 1)
                               if (i == len(ws)) s][0];
function cs_merged(ws, d_min, d_max) = cs_clamp(max(pow(cs_cube_sum(ws), 1 / 3), max(ws)), d_min, d_max);
function cs_angle(a, b) = atan2(norm([b[0] - a[0], b[1] - a[1]]), abs(a[2] - b[2]));
// core/rules.cpp min_n_width: narrower, an N-profile's three walls leave no gaps between them.
function cs_min_n_width(wall) = 3 * wall;

// ----------------------------------------------------------------------------- the tree, derived

// Fixed points, by a C-style list comprehension (no recursion): a state [x, step(x)] moves on
// until the step changes nothing; the last step's result is the fixed point (cs_last). Each
// derived list below settles after as many steps as the tree is deep. One step function per list
// (function literals would do, but keep the file plain).
function cs_last(steps, start) = len(steps) == 0 ? start : steps[len(steps) - 1];

// Per node: the struts ending there, and the strut leaving it (-1: none), among `keep`.
function cs_incoming(n, struts, keep) =
    n == 0 ? [] : [for (v = [0 : n - 1]) [for (e = search(v, struts, 0, 1)) if (keep[e]) e]];
function cs_outgoing(n, struts, keep) =
    n == 0 ? [] : [for (v = [0 : n - 1]) let(f = [for (e = search(v, struts, 0, 0)) if (keep[e]) e]) len(f) ? f[0] : -1];

// Omitted struts and their branches: a strut goes when it is omitted or the strut below it goes.
function cs_gone_step(g, struts, out, direct) =
    [for (e = [0 : len(struts) - 1]) direct[e] ? true : out[struts[e][1]] < 0 ? false : g[out[struts[e][1]]]];
function cs_gone(n, struts, omit) =
    len(struts) == 0 ? [] :
    let(all = [for (e = struts) true],
        out = cs_outgoing(n, struts, all),
        direct = [for (e = [0 : len(struts) - 1]) len(search(e, omit)) > 0])
    cs_last([for (s = [direct, cs_gone_step(direct, struts, out, direct)]; s[0] != s[1];
                  s = [s[1], cs_gone_step(s[1], struts, out, direct)]) s[1]], direct);

// Runs: per strut [length above it in its run (itself included), steepest above, length below,
// steepest below]; a bend is a node with one strut in and one out that is not a leaf.
function cs_runs_step(r, struts, lens, angles, node_in, out, bend) =
    [for (e = [0 : len(struts) - 1])
        let(t = struts[e][0], b = struts[e][1],
            above = bend[t] ? r[node_in[t][0]] : [0, 0, 0, 0],
            below = bend[b] ? r[out[b]] : [0, 0, 0, 0])
        [lens[e] + above[0], max(angles[e], above[1]), lens[e] + below[2], max(angles[e], below[3])]];
function cs_runs(struts, lens, angles, node_in, out, bend) =
    len(struts) == 0 ? [] :
    let(start = [for (e = struts) [0, 0, 0, 0]])
    cs_last([for (s = [start, cs_runs_step(start, struts, lens, angles, node_in, out, bend)]; s[0] != s[1];
                  s = [s[1], cs_runs_step(s[1], struts, lens, angles, node_in, out, bend)]) s[1]], start);

function cs_node_width(v, node_in, w, d_min, d_max) =
    len(node_in[v]) == 0 ? d_min
    : len(node_in[v]) == 1 ? w[node_in[v][0]][1]
    : cs_merged([for (e = node_in[v]) w[e][1]], d_min, d_max);

// [upper, lower] width of strut e, given the widths `w` of the struts above it.
function cs_size_strut(e, s, nodes, node_in, run, w, k, d_min, d_max, strength_length) =
    let(a = nodes[s[0]], b = nodes[s[1]],
        up = cs_clamp(max(cs_node_width(s[0], node_in, w, d_min, d_max),
                          cs_strength_width(run[0], run[1], strength_length)), d_min, d_max))
    [up, max(up, cs_eqn1(k, norm(b - a), cs_angle(a, b), d_min, d_max))];

// A strut's sizing level: the longest path (in struts) from a leaf down to its top node. Levels
// settle in cheap integer steps; widths then take one pass per level, each strut sized once.
function cs_levels_step(lv, struts, node_in) =
    [for (e = [0 : len(struts) - 1])
        let(into = node_in[struts[e][0]]) len(into) == 0 ? 0 : max([for (f = into) lv[f]]) + 1];
function cs_strut_levels(struts, node_in) =
    len(struts) == 0 ? [] :
    let(start = [for (s = struts) 0])
    cs_last([for (s = [start, cs_levels_step(start, struts, node_in)]; s[0] != s[1];
                  s = [s[1], cs_levels_step(s[1], struts, node_in)]) s[1]], start);

// Level by level: every strut into a node is sized before the node's own strut.
function cs_strut_widths(nodes, node_in, struts, runs, levels, k, d_min, d_max, strength_length) =
    len(struts) == 0 ? [] :
    let(last = max(levels))
    [for (L = 0, w = [for (s = struts) [d_min, d_min]];
          L <= last + 1;
          w = [for (e = [0 : len(struts) - 1])
                  levels[e] == L ? cs_size_strut(e, struts[e], nodes, node_in, runs[e], w, k, d_min, d_max, strength_length)
                                 : w[e]],
          L = L + 1)
        if (L == last + 1) w][0];

// Everything the geometry needs, derived from a tree record: [keep, node_in, out, runs, widths, room].
function cs_derive(tree, omit, k, d_min, d_max, strength_length) =
    let(nodes = tree[0], struts = tree[1], leaves = tree[2], beds = tree[4], n = len(nodes),
        gone = cs_gone(n, struts, omit),
        keep = [for (g = gone) !g],
        node_in = cs_incoming(n, struts, keep),
        out = cs_outgoing(n, struts, keep),
        is_leaf = n == 0 ? [] : [for (v = [0 : n - 1]) len(search(v, leaves, 1, 0)) > 0],
        bend = n == 0 ? [] : [for (v = [0 : n - 1]) len(node_in[v]) == 1 && out[v] >= 0 && !is_leaf[v]],
        lens = [for (s = struts) norm(nodes[s[0]] - nodes[s[1]])],
        angles = [for (s = struts) cs_angle(nodes[s[0]], nodes[s[1]])],
        r = cs_runs(struts, lens, angles, node_in, out, bend),
        runs = [for (e = [0 : max(0, len(struts) - 1)]) if (e < len(struts))
                   [r[e][0] + r[e][2] - lens[e], max(r[e][1], r[e][3])]],
        w = cs_strut_widths(nodes, node_in, struts, runs, cs_strut_levels(struts, node_in), k, d_min, d_max,
                            strength_length),
        room = n == 0 ? [] : [for (v = [0 : n - 1]) let(f = search(v, beds, 1, 0)) len(f) ? beds[f[0]][1] : -1])
    [keep, node_in, out, runs, w, room];

// ----------------------------------------------------------------------------- solids

// The N of the paper's Fig. 10 in a d x d square: left bar, right bar and the diagonal from the
// top-left to the bottom-right corner, as one polygon of 12 corners (counter-clockwise).
function cs_n_ring(d, t) = let(a = d / 2, c = t / sqrt(2))
    [[-a, -a], [-a + t, -a], [-a + t, a - t - c], [a - t, -a + t - c], [a - t, -a], [a, -a],
     [a, a], [a - t, a], [a - t, -a + t + c], [-a + t, a - t + c], [-a + t, a], [-a, a]];
cs_n_cap = [[0, 1, 2], [0, 2, 9], [0, 9, 11], [9, 10, 11], [4, 5, 6], [4, 6, 3], [3, 6, 8], [8, 6, 7],
            [2, 3, 8], [2, 8, 9]];
function cs_square_ring(d) = let(a = d / 2) [[-a, -a], [a, -a], [a, a], [-a, a]];
cs_square_cap = [[0, 1, 2], [0, 2, 3]];

module cs_prism(bottom, top, w_bottom, w_top, n_profile, wall) {
    lo = n_profile ? cs_n_ring(w_bottom, wall) : cs_square_ring(w_bottom);
    hi = n_profile ? cs_n_ring(w_top, wall) : cs_square_ring(w_top);
    cap = n_profile ? cs_n_cap : cs_square_cap;
    n = len(lo);
    // OpenSCAD wants faces clockwise seen from outside.
    polyhedron(
        points = concat([for (q = lo) [bottom[0] + q[0], bottom[1] + q[1], bottom[2]]],
                        [for (q = hi) [top[0] + q[0], top[1] + q[1], top[2]]]),
        faces = concat([for (t = cap) [t[0], t[1], t[2]]],
                       [for (t = cap) [n + t[0], n + t[2], n + t[1]]],
                       [for (i = [0 : n - 1]) [i, n + (i + 1) % n, (i + 1) % n]],
                       [for (i = [0 : n - 1]) [i, n + i, n + (i + 1) % n]]),
        convexity = 4);
}

module cs_strut(a, b, w_a, w_b, wall, min_n) {
    cs_prism(b, a, w_b, w_a, min(w_a, w_b) >= min_n, wall);
}

// A tip from `bottom` (width w_bottom, inside its strut's top) up to `top` (tip_diameter): one
// taper along the line the generator tested for clearance (core/rules.hpp, leaf_tip). A tip whose
// top sits aside of its leaf slants; a neck would bend it off that line.
module cs_tip(bottom, top, w_bottom, tip_diameter, wall) {
    cs_prism(bottom, top, w_bottom, tip_diameter, false, wall);
}

// A tip standing on the model: one taper up from `bottom` (tip_diameter) to its node (w_top).
module cs_contact_tip(bottom, top, tip_diameter, w_top, wall) {
    cs_prism(bottom, top, tip_diameter, w_top, false, wall);
}

// Half-way up its strut at most; as wide as the room to the model allows (minus the clearance),
// and left out when under 0.25 mm would remain.
function cs_foot_extra(foot_extra, w, room, clearance) = let(e = min(foot_extra, room / sqrt(2) - w / 2 - clearance))
    e >= 0.25 ? e : 0;

function cs_foot_top(bed_point, toward, foot_height) =
    bed_point + (toward - bed_point) * min(0.5, foot_height / toward[2]);

module cs_foot(bed_point, toward, w, foot_height, foot_extra, room, clearance, wall) {
    e = cs_foot_extra(foot_extra, w, room, clearance);
    if (e > 0) cs_prism(bed_point, cs_foot_top(bed_point, toward, foot_height), w + 2 * e, w, false, wall);
}

module cs_tree(tree, omit, highlight, k, d_min, d_max, strength_length, wall, tip_length, tip_diameter, feet,
               foot_height, foot_extra, clearance) {
    nodes = tree[0]; struts = tree[1]; leaves = tree[2]; contacts = tree[3]; pillars = tree[5]; overlap = tree[6];
    derived = cs_derive(tree, omit, k, d_min, d_max, strength_length);
    keep = derived[0]; node_in = derived[1]; out = derived[2]; w = derived[4]; room = derived[5];
    for (e = [0 : max(0, len(struts) - 1)]) if (e < len(struts) && keep[e]) {
        a = nodes[struts[e][0]];
        b0 = nodes[struts[e][1]];
        on_bed = room[struts[e][1]] >= 0;
        has_foot = on_bed && feet && foot_height > 0 && cs_foot_extra(foot_extra, w[e][1], room[struts[e][1]], clearance) > 0;
        down = (b0 - a) / norm(b0 - a);
        // Onto a joint: reach `overlap` into it; onto a foot: stop just inside the foot's top.
        b = !on_bed ? b0 + down * overlap : has_foot ? cs_foot_top(b0, a, foot_height) + down * overlap : b0;
        color(e == highlight ? "red" : "darkorange") {
            cs_strut(a, b, w[e][0], w[e][1], wall, cs_min_n_width(wall));
            if (has_foot) cs_foot(b0, a, w[e][1], foot_height, foot_extra, room[struts[e][1]], clearance, wall);
        }
    }
    color("darkorange") {
        for (l = leaves) if (out[l[0]] >= 0)
            cs_tip(nodes[l[0]] - [0, 0, overlap], l[2], w[out[l[0]]][0], tip_diameter, wall);
        for (c = contacts) if (len(node_in[c[0]]) > 0)
            cs_contact_tip(c[1], nodes[c[0]], tip_diameter, w[node_in[c[0]][0]][1], wall);
        for (i = [0 : max(0, len(pillars) - 1)]) if (i < len(pillars) && len(search(len(struts) + i, omit)) == 0)
            cs_prism(pillars[i][1], pillars[i][0], d_min, tip_diameter, false, wall);
    }
}

// A wall under a low ceiling (generator/ceilings): a box w[4] thick across the line from w[0] to
// w[1], from z = w[2] up to z = w[3]; one polyhedron with explicit triangles.
module cs_wall(w) {
    t = w[4];
    along = w[1] - w[0];
    o = [-along[1], along[0]] * (t / 2 / norm(along));
    polyhedron(
        points = [for (c = [w[0], w[1]]) each [[c[0] - o[0], c[1] - o[1], w[2]], [c[0] + o[0], c[1] + o[1], w[2]],
                                                [c[0] + o[0], c[1] + o[1], w[3]], [c[0] - o[0], c[1] - o[1], w[3]]]],
        faces = concat([[0, 1, 2], [0, 2, 3], [4, 6, 5], [4, 7, 6]],
                       [for (i = [0 : 3]) let(b = (i + 1) % 4) [i, b + 4, b]],
                       [for (i = [0 : 3]) let(b = (i + 1) % 4) [i, i + 4, b + 4]]),
        convexity = 2);
}

// The walls, without the hybrid pieces standing on tips that `omit` takes out of `tree` (the tree
// record cs_tree draws): a piece off the bed whose foot's middle is such a tip's top goes with it,
// as the generator's prune_pieces (pipeline.hpp) decides; else it would hang in the air. Files
// written by earlier versions call cs_walls(walls) alone: every wall is drawn.
module cs_walls(walls, tree = undef, omit = []) {
    gone_tops = cs_gone_tip_tops(tree, omit);
    color("darkorange") for (w = walls) if (!cs_on_tip_among(w, gone_tops)) cs_wall(w);
}

// The tops of the tips that `omit` takes out of a tree record (a leaf's tip goes with the strut
// leaving the leaf, as in cs_tree).
function cs_gone_tip_tops(tree, omit) =
    is_undef(tree) || len(omit) == 0 || len(tree[1]) == 0 ? [] :
    let(n = len(tree[0]), struts = tree[1],
        gone = cs_gone(n, struts, omit),
        out = cs_outgoing(n, struts, [for (e = struts) true]))
    [for (l = tree[2]) if (out[l[0]] >= 0 && gone[out[l[0]]]) l[2]];

// Does wall w stand off the bed on one of the tips whose tops are `tops` (the middle of its foot,
// as near as the data's 4 decimals put them)?
function cs_on_tip_among(w, tops) =
    w[2] > 0 && len([for (t = tops) if (norm([(w[0][0] + w[1][0]) / 2, (w[0][1] + w[1][1]) / 2, w[2]] - t) < 1e-3) 1]) > 0;

// A user's support blockers (see-through blue) and support points (red) in the preview only:
// never part of a rendered solid.
module cs_show_edits(blockers, points) {
    if ($preview) {
        for (b = blockers) color([0.2, 0.4, 1, 0.3]) translate(b[0]) cube(b[1] - b[0]);
        for (q = points) color("red") translate(q) sphere(r = 0.6, $fn = 16);
    }
}
