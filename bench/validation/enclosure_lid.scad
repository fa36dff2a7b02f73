// Validation part (bench/validation): an electronics enclosure and its lid,
// laid out side by side as a user would print them without turning the lid over.
// Exercises: enclosures with lids. The box's side walls carry a round cable
// port and a rectangular USB port (a bore and a flat-topped slot), its inside
// four screw bosses, its outside two mounting ears. The lid lies top face up:
// its whole underside is a flat roof low over the bed (on its 3 mm locating
// rim), with a hole for a button and four countersunk screw holes.
// Units: mm. Never used to tune the generator (see bench/README.md).

/* [Box] */
// Outside size of the box (mm)
box = [60, 40, 25];      // [x, y, z]
// Wall thickness (mm)
wall = 2;                // [1.2:0.2:4]
// Floor thickness (mm)
floor_t = 2;             // [1.2:0.2:4]
// Cable port diameter (mm)
port_d = 8;              // [3:0.5:15]
// USB slot width and height (mm)
usb = [12, 6];

/* [Lid] */
// Lid thickness (mm)
lid_t = 2;               // [1.2:0.2:4]
// Height of the locating rim under the lid (mm)
rim_h = 3;               // [1:0.5:6]
// Button hole diameter (mm)
button_d = 12;           // [0:1:20]
// Gap between the box and the lid on the bed (mm)
gap = 8;

/* [Resolution] */
$fn = 40;                // [16:4:96]

boss_d = 6;
screw_d = 2.6;
boss_at = [[wall + 4, wall + 4], [box[0] - wall - 4, wall + 4],
           [wall + 4, box[1] - wall - 4], [box[0] - wall - 4, box[1] - wall - 4]];

module box_part() {
    difference() {
        union() {
            difference() {
                cube(box);
                translate([wall, wall, floor_t]) cube([box[0] - 2 * wall, box[1] - 2 * wall, box[2]]);
            }
            for (p = boss_at) translate([p[0], p[1], 0]) cylinder(d = boss_d, h = box[2] - 1);
            // mounting ears at both ends, 6 mm up the wall (they overhang the bed)
            for (x = [-8, box[0]]) translate([x, box[1] / 2 - 6, 6]) cube([8, 12, 3]);
        }
        for (p = boss_at) translate([p[0], p[1], floor_t]) cylinder(d = screw_d, h = box[2]);
        for (x = [-4, box[0] + 4]) translate([x, box[1] / 2, 5]) cylinder(d = 3.4, h = 5);
        // round cable port in the -y wall, rectangular USB slot in the +x wall
        translate([box[0] / 3, -1, box[2] / 2]) rotate([-90, 0, 0]) cylinder(d = port_d, h = wall + 2);
        translate([box[0] - wall - 1, box[1] / 2 - usb[0] / 2, 8]) cube([wall + 2, usb[0], usb[1]]);
    }
}

module lid_part() {
    inner = [box[0] - 2 * wall - 0.4, box[1] - 2 * wall - 0.4];
    difference() {
        union() {
            translate([0, 0, rim_h]) cube([box[0], box[1], lid_t]);
            // locating rim: a thin frame that fits inside the box walls
            translate([wall + 0.2, wall + 0.2, 0]) difference() {
                cube([inner[0], inner[1], rim_h]);
                translate([1.2, 1.2, -1]) cube([inner[0] - 2.4, inner[1] - 2.4, rim_h + 2]);
            }
        }
        translate([box[0] / 2, box[1] / 2, -1]) cylinder(d = button_d, h = rim_h + lid_t + 2);
        for (p = boss_at) translate([p[0], p[1], rim_h - 1]) {
            cylinder(d = 3, h = lid_t + 2);
            translate([0, 0, lid_t - 0.5]) cylinder(d1 = 3, d2 = 6, h = 1.52);
        }
    }
}

box_part();
translate([0, box[1] + gap, 0]) lid_part();
