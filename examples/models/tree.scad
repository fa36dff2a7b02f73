// clever-support example: stylised tree
// Echoes the "tree" model of Vanek et al., "Clever Support", SGP 2014.
// A trunk rises from a flared root disc; branches leave the trunk at low
// elevation angles and end in flattened (elliptic) foliage blobs whose
// undersides are large horizontal-ish overhangs.
// Units: mm.  Base is flat on z = 0.
// Same licence as the clever-support project.

/* [Trunk] */
// Height of the trunk axis (mm)
trunk_height = 45;       // [25:1:60]
// Trunk radius at the ground (mm)
trunk_radius_bottom = 5; // [3:0.5:8]
// Trunk radius at the top (mm)
trunk_radius_top = 3;    // [1.5:0.5:6]
// Radius of the flared root disc (mm)
root_radius = 9;         // [5:0.5:14]
// Height of the root flare (mm)
root_height = 4;         // [1:0.5:8]

/* [Branches] */
// Horizontal reach of the branches from the trunk axis (mm)
branch_reach = 27;       // [12:1:34]
// Elevation of the branches above horizontal (deg); < 40 means they overhang
branch_elevation = 22;   // [0:1:40]
// Branch radius where it leaves the trunk (mm)
branch_radius_root = 2.4;// [1:0.2:4]
// Branch radius at the foliage (mm)
branch_radius_tip = 1.4; // [0.8:0.2:3]

/* [Foliage] */
// Radius of the crown blob on top of the trunk (mm)
crown_radius = 12;       // [6:0.5:18]
// Radius of the foliage blobs at the branch tips (mm)
blob_radius = 9;         // [4:0.5:14]
// Vertical squash of the foliage blobs (1 = spheres)
blob_squash = 0.7;       // [0.4:0.05:1]

/* [Resolution] */
// Facets on full circles
$fn = 32;                // [16:4:64]

// ---------------------------------------------------------------------------
// Branches: [height on trunk (mm), azimuth (deg), reach scale, blob scale]
branches = [
    [0.45 * trunk_height,   0, 1.00, 1.00],
    [0.55 * trunk_height, 130, 0.90, 0.90],
    [0.65 * trunk_height, 245, 0.95, 0.95],
    [0.78 * trunk_height,  60, 0.85, 0.70],
    [0.84 * trunk_height, 185, 0.80, 0.65],
];

// Cone frustum from point a (radius ra) to point b (radius rb).
module segment(a, b, ra, rb) {
    d = b - a;
    len = norm(d);
    translate(a)
        rotate([0, acos(d[2] / len), atan2(d[1], d[0])])
            cylinder(h = len, r1 = ra, r2 = rb);
}

module blob(r) {
    scale([1, 1, blob_squash]) sphere(r = r);
}

// Tip of a branch given its table row.
function branch_tip(b) =
    let(reach = branch_reach * b[2])
    [reach * cos(b[1]), reach * sin(b[1]),
     b[0] + reach * tan(branch_elevation)];

module tree() {
    union() {
        // root flare + trunk
        cylinder(h = root_height, r1 = root_radius, r2 = trunk_radius_bottom);
        cylinder(h = trunk_height, r1 = trunk_radius_bottom,
                 r2 = trunk_radius_top);
        // crown
        translate([0, 0, trunk_height + 0.4 * crown_radius * blob_squash])
            blob(crown_radius);
        // branches with foliage
        for (b = branches) {
            tip = branch_tip(b);
            segment([0, 0, b[0]], tip, branch_radius_root, branch_radius_tip);
            translate(tip) blob(blob_radius * b[3]);
        }
    }
}

tree();
