// Validation part (bench/validation): a shelf bracket, printed as it is mounted.
// Exercises: brackets. A wall plate stands on its lower edge; a shelf arm
// sticks out horizontally at the top, carried by a 45 deg brace that needs no
// support. The arm's underside beyond the brace, its screw holes (vertical:
// none) and the wall plate's two horizontal countersunk screw holes (bores) do.
// Units: mm. Never used to tune the generator (see bench/README.md).

/* [Bracket] */
// Height of the wall plate (mm)
plate_h = 50;           // [30:1:80]
// Width of the bracket (mm)
width = 16;             // [10:1:30]
// Thickness of plate and arm (mm)
t = 4;                  // [2:0.5:8]
// Length of the shelf arm (mm)
arm_l = 45;             // [25:1:80]
// How far out the brace reaches under the arm (mm)
brace_l = 28;           // [10:1:60]
// Thickness of the brace (mm)
brace_t = 4;            // [2:0.5:8]
// Screw hole diameter (mm)
screw_d = 4.5;          // [3:0.1:6]
// Countersink head diameter (mm)
head_d = 9;             // [6:0.5:12]
// Lip at the arm's front end (mm, 0 = none)
lip_h = 4;              // [0:0.5:8]

/* [Resolution] */
$fn = 40;               // [16:4:96]

module bracket() {
    difference() {
        union() {
            cube([t, width, plate_h]);                                  // wall plate
            translate([0, 0, plate_h - t]) cube([arm_l, width, t]);     // shelf arm
            translate([arm_l - t, 0, plate_h]) cube([t, width, lip_h]); // lip (up)
            // 45 deg brace from the plate up to the arm
            hull() {
                translate([0, 0, plate_h - t - brace_l]) cube([t, width, brace_t]);
                translate([brace_l, 0, plate_h - t - 0.01]) cube([brace_t, width, 0.01]);
            }
        }
        // two countersunk screw holes through the plate (horizontal bores)
        for (z = [8, plate_h - t - brace_l - 8])
            translate([-0.01, width / 2, z]) rotate([0, 90, 0]) {
                cylinder(d = screw_d, h = t + 1);
                translate([0, 0, t - (head_d - screw_d) / 2]) cylinder(d1 = screw_d, d2 = head_d, h = (head_d - screw_d) / 2 + 0.02);
            }
        // two screw holes down through the arm
        for (x = [t + 10, arm_l - 12])
            translate([x, width / 2, plate_h - t - 1]) cylinder(d = screw_d, h = t + 2);
    }
}

bracket();
