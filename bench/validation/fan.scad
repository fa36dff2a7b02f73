// Validation part (bench/validation): a four-blade fan standing on its hub.
// Exercises: tapered blades. Each blade is a flat plate that narrows from root to tip (chord 16 to
// 7 mm) and twists (pitch 25 deg at the root, 12 at the tip); its underside is a long sloped
// ceiling 3-11 mm over the bed whose edges turn in towards the tip. The hub's bore is vertical.
// Units: mm. Written 2026-12-06; never used to tune the generator (see bench/README.md).

/* [Hub] */
// Hub diameter (mm)
hub_d = 18;             // [10:1:30]
// Hub height (mm)
hub_h = 14;             // [8:1:30]
// Shaft bore (mm)
bore_d = 6;             // [2:0.5:10]

/* [Blades] */
// Number of blades
blades = 4;             // [2:1:8]
// Radius of the blade tips (mm)
tip_r = 40;             // [20:1:80]
// Chord at the root and at the tip (mm)
chord = [16, 7];
// Pitch at the root and at the tip (deg from horizontal)
pitch = [25, 12];
// Blade thickness (mm)
blade_t = 1.4;          // [0.8:0.2:4]
// Stations along the blade
stations = 5;           // [2:1:12]
// Angle of the first blade (deg)
first = 10;             // [0:1:90]

// The blade's cross-section at station i: a thin plate turned to its pitch.
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

difference() {
    union() {
        cylinder(d = hub_d, h = hub_h, $fn = 48);
        for (k = [0:blades - 1]) rotate([0, 0, 360 * k / blades + first]) blade();
    }
    translate([0, 0, -1]) cylinder(d = bore_d, h = hub_h + 2, $fn = 24);
}
