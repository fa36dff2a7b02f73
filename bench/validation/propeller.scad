// Validation part (bench/validation): a three-blade propeller standing on its hub.
// Exercises: blades. Each blade is a thin twisted plate (pitch 35 deg at the
// root, 20 deg at the tip) whose underside is a long, narrow, sloped ceiling
// between about 3 and 12 mm over the bed; supports must reach all along it
// without many tiny islands per layer. The hub's bore is vertical (no support).
// Units: mm. Never used to tune the generator (see bench/README.md).

/* [Hub] */
// Hub diameter (mm)
hub_d = 14;             // [8:1:30]
// Hub height (mm)
hub_h = 12;             // [6:1:30]
// Shaft bore (mm)
bore_d = 5;             // [2:0.5:10]

/* [Blades] */
// Number of blades
blades = 3;             // [2:1:6]
// Radius of the blade tips (mm)
tip_r = 45;             // [20:1:80]
// Chord at the root and at the tip (mm)
chord = [14, 9];
// Pitch at the root and at the tip (deg from horizontal)
pitch = [35, 20];
// Blade thickness (mm)
blade_t = 1.6;          // [0.8:0.2:4]
// Stations along the blade (more = smoother twist)
stations = 6;           // [2:1:12]

/* [Resolution] */
$fn = 40;               // [16:4:96]

// The blade's cross-section at radius r: a thin plate turned to its pitch.
module section(i) {
    f = i / stations;
    r = hub_d / 2 - 1 + f * (tip_r - hub_d / 2 + 1);
    c = chord[0] + f * (chord[1] - chord[0]);
    p = pitch[0] + f * (pitch[1] - pitch[0]);
    translate([r, 0, hub_h / 2]) rotate([p, 0, 0]) cube([0.2, c, blade_t], center = true);
}

module blade() {
    for (i = [0:stations - 1]) hull() { section(i); section(i + 1); }
}

module propeller() {
    difference() {
        union() {
            cylinder(d = hub_d, h = hub_h);
            for (k = [0:blades - 1]) rotate([0, 0, 360 * k / blades]) blade();
        }
        translate([0, 0, -1]) cylinder(d = bore_d, h = hub_h + 2, $fn = 24);
    }
}

propeller();
