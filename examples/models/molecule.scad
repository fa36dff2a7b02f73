// clever-support example: ball-and-stick molecule (ethanol, CH3-CH2-OH)
// Echoes the ball-and-stick "molecule" of Vanek et al., "Clever Support",
// SGP 2014.  The molecule stands on one hydrogen atom whose C-H bond is
// vertical; that atom sits on a small round pad touching the bed.  Every
// other atom and bond hangs in the air, so almost every ball has an
// overhanging underside and the near-horizontal bonds need support too.
// Geometry: idealised tetrahedral (109.47 deg) bond angles, staggered.
// Units: mm (model scale in mm per Angstrom).  Base is flat on z = 0.
// Same licence as the clever-support project.

/* [Scale] */
// Model scale (mm per Angstrom of bond length)
mm_per_angstrom = 15;   // [8:0.5:20]

/* [Atom radii (mm)] */
// Carbon ball radius
r_carbon = 6.5;         // [3:0.5:10]
// Oxygen ball radius
r_oxygen = 6;           // [3:0.5:10]
// Hydrogen ball radius
r_hydrogen = 4;         // [2:0.5:7]

/* [Bonds] */
// Bond (stick) radius
r_bond = 1.8;           // [1:0.1:3]

/* [Pad] */
// Radius of the pad under the standing atom
pad_radius = 7;         // [3:0.5:12]
// Thickness of the pad
pad_height = 1.6;       // [0.4:0.2:4]

/* [Resolution] */
// Facets on full circles
$fn = 28;               // [12:4:48]

// ---------------------------------------------------------------------------
// Bond lengths (Angstrom)
L_CC = 1.54;
L_CH = 1.09;
L_CO = 1.43;
L_OH = 0.96;

// Tetrahedral directions: one straight down, three at
// asin(1/3) = 19.47 deg above horizontal, 120 deg apart.
e = asin(1 / 3);
function up(a) = [cos(e) * cos(a), cos(e) * sin(a), sin(e)];
DOWN = [0, 0, -1];

s = mm_per_angstrom;

// Atom 0 (C1) is the origin of the molecule frame.  C2 lies along up(0);
// its own (staggered) tetrahedral set is the negated one: -up(0) back to
// C1, [0,0,1], -up(120), -up(240).  O sits on C2 along -up(120); the O's
// set is again the un-negated one, and its H points along up(0).
C1  = [0, 0, 0];
H1  = C1 + s * L_CH * DOWN;          // the atom the molecule stands on
H2  = C1 + s * L_CH * up(120);
H3  = C1 + s * L_CH * up(240);
C2  = C1 + s * L_CC * up(0);
H4  = C2 + s * L_CH * [0, 0, 1];
O   = C2 - s * L_CO * up(120);
H5  = C2 - s * L_CH * up(240);
H6  = O  + s * L_OH * up(0);

// [position, radius]
atoms = [
    [C1, r_carbon], [C2, r_carbon], [O, r_oxygen],
    [H1, r_hydrogen], [H2, r_hydrogen], [H3, r_hydrogen],
    [H4, r_hydrogen], [H5, r_hydrogen], [H6, r_hydrogen],
];
// pairs of indices into atoms
bonds = [[0, 1], [1, 2], [0, 3], [0, 4], [0, 5], [1, 6], [1, 7], [2, 8]];

// Lift so that the bottom atom (H1) rests on the pad: the pad top cuts the
// ball 1 mm above its lowest point, giving a solid contact disc.
lift = -H1[2] + r_hydrogen + pad_height - 1;

// Cylinder from point a to point b.
module stick(a, b, r) {
    d = b - a;
    len = norm(d);
    translate(a)
        rotate([0, acos(d[2] / len), atan2(d[1], d[0])])
            cylinder(h = len, r = r);
}

module molecule() {
    union() {
        cylinder(h = pad_height, r = pad_radius);
        translate([0, 0, lift]) {
            for (a = atoms) translate(a[0]) sphere(r = a[1]);
            for (b = bonds) stick(atoms[b[0]][0], atoms[b[1]][0], r_bond);
        }
    }
}

molecule();
