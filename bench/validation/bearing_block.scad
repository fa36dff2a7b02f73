// Validation part (bench/validation): a flanged bearing block (pillow block).
// Exercises: bores and flanges. A base plate with two slotted bolt holes
// carries a housing whose bearing bore (a 22 mm seat for a 608 bearing, with a
// smaller shaft bore beyond it) runs horizontally: a round ceiling 16-33 mm over
// the bed. A flange around the bore's mouth overhangs the housing on every
// side, and a grease hole drops vertically into the bore from the top.
// Units: mm. Never used to tune the generator (see bench/README.md).

/* [Base] */
// Base plate size (mm)
base = [64, 22, 6];      // [x, y, z]
// Bolt slot width and length (mm)
slot = [5.5, 9];

/* [Housing] */
// Bearing seat diameter and depth (mm)
seat = [22.2, 7];
// Shaft bore diameter (mm)
shaft_d = 12;            // [5:0.5:20]
// Height of the bore axis above the bed (mm)
axis_z = 22;             // [14:1:40]
// Housing outside diameter (mm)
housing_d = 34;          // [26:1:50]
// Flange diameter and thickness (mm)
flange = [42, 4];

/* [Resolution] */
$fn = 56;                // [24:4:96]

module housing_body() {
    // a round housing on a web down to the base, bore axis along y
    translate([0, 0, axis_z]) rotate([-90, 0, 0]) cylinder(d = housing_d, h = base[1]);
    translate([-housing_d / 2, 0, 0]) cube([housing_d, base[1], axis_z]);
    translate([0, base[1], axis_z]) rotate([-90, 0, 0]) cylinder(d = flange[0], h = flange[1]);
}

module block() {
    difference() {
        union() {
            translate([-base[0] / 2, 0, 0]) cube(base);
            housing_body();
        }
        // bearing seat from the flange side, shaft bore through
        translate([0, base[1] + flange[1] - seat[1], axis_z]) rotate([-90, 0, 0]) cylinder(d = seat[0], h = seat[1] + 1);
        translate([0, -1, axis_z]) rotate([-90, 0, 0]) cylinder(d = shaft_d, h = base[1] + flange[1] + 2);
        // grease hole from the top
        translate([0, base[1] + flange[1] - seat[1] / 2, axis_z]) cylinder(d = 3, h = housing_d);
        // slotted bolt holes in the base
        for (s = [-1, 1]) translate([s * (base[0] / 2 - 8), base[1] / 2, -1]) hull()
            for (dx = [-(slot[1] - slot[0]) / 2, (slot[1] - slot[0]) / 2])
                translate([dx, 0, 0]) cylinder(d = slot[0], h = base[2] + 2, $fn = 24);
    }
}

block();
