// Validation part (bench/validation): a cable clip with a snap hook, printed on its back.
// Exercises: thin curved overhangs and a hook. A 3 mm base strip with a
// screw hole carries an open ring (a C whose upper half is a round ceiling
// curling over the cable channel) and, beside it, a snap tongue with a barb
// whose underside is a flat ledge 10 mm over the base.
// Units: mm. Never used to tune the generator (see bench/README.md).

/* [Clip] */
// Cable diameter (mm)
cable_d = 10;            // [4:0.5:20]
// Ring wall thickness (mm)
ring_t = 2;              // [1.2:0.2:4]
// Opening of the C at the top (deg)
opening = 45;            // [30:5:120]
// Clip width along the cable (mm)
width = 12;              // [6:1:25]
// Base strip length and thickness (mm)
base = [40, 3];
// Screw hole (mm)
screw_d = 3.5;           // [2:0.1:6]

/* [Resolution] */
$fn = 48;                // [24:4:96]

module c_ring() {
    r = cable_d / 2;
    translate([0, 0, base[1] + r]) rotate([90, 0, 0]) linear_extrude(height = width, center = true)
        difference() {
            circle(r = r + ring_t);
            circle(r = r);
            // the opening at the top, centred on +y of the 2-D plane (= +z)
            polygon([[0, 0], [2 * (r + ring_t) * sin(opening / 2) / cos(opening / 2), 2 * (r + ring_t)],
                     [-2 * (r + ring_t) * sin(opening / 2) / cos(opening / 2), 2 * (r + ring_t)]]);
        }
}

module snap_tongue() {
    translate([0, -width / 2, 0]) {
        cube([2, width, base[1] + 12]);
        // barb: flat underside 10 mm over the base, sloped top
        translate([0, 0, base[1] + 10]) rotate([90, 0, 0]) mirror([0, 0, 1])
            linear_extrude(height = width) polygon([[0, 0], [-3, 0], [0, 3]]);
    }
}

difference() {
    union() {
        translate([-base[0] / 2, -width / 2, 0]) cube([base[0], width, base[1]]);
        c_ring();
        translate([cable_d / 2 + ring_t + 6, 0, 0]) snap_tongue();
    }
    translate([-base[0] / 2 + 5, 0, -1]) cylinder(d = screw_d, h = base[1] + 2);
}
