// clever-support example: spoked wheel standing upright
// Echoes the "wheel" model of Vanek et al., "Clever Support", SGP 2014.
// The wheel axis is horizontal (along y).  A rounded tyre/rim is joined to
// a hub by straight spokes.  The bottom of the tyre is cut flat to give a
// contact patch on the bed.  Overhangs: the lower outside of the tyre, the
// inner (downward-facing) surface of the upper rim, the horizontal spokes,
// the undersides of the hub and of the axle hole.
// Units: mm.  Base (contact patch) is flat on z = 0.
// Same licence as the clever-support project.

/* [Rim / tyre] */
// Outer diameter of the wheel (mm)
outer_diameter = 70;     // [40:1:80]
// Radial thickness of the rim ring (mm)
rim_thickness = 6;       // [3:0.5:12]
// Width of the rim along the axle (mm)
rim_width = 10;          // [5:0.5:20]
// Edge rounding radius of the rim profile (mm)
rim_rounding = 2.5;      // [0.5:0.5:5]
// Depth of the flat cut at the bottom (mm); gives the contact patch
flat_depth = 1.0;        // [0.3:0.1:3]

/* [Hub] */
// Hub diameter (mm)
hub_diameter = 16;       // [8:1:30]
// Hub length along the axle (mm)
hub_length = 14;         // [5:1:25]
// Axle hole diameter (mm), 0 for none
axle_diameter = 5;       // [0:0.5:10]

/* [Spokes] */
// Number of spokes
spoke_count = 8;         // [3:1:16]
// Spoke diameter (mm)
spoke_diameter = 3.2;    // [1.5:0.1:6]
// Rotation of the spoke pattern (deg); 0 puts spokes exactly horizontal
spoke_phase = 0;         // [0:1:90]

/* [Resolution] */
// Facets on full circles (the tyre sweep uses 2x)
$fn = 40;                // [16:4:96]

// ---------------------------------------------------------------------------
R = outer_diameter / 2;
r_in = R - rim_thickness;
rr = min(rim_rounding, rim_thickness / 2 - 0.01, rim_width / 2 - 0.01);

// Rim: rounded rectangle profile swept around the axle (z axis in this
// local frame; the whole wheel is rotated onto the y axis later).
module rim() {
    rotate_extrude($fn = 2 * $fn)
        translate([r_in, -rim_width / 2])
            offset(r = rr, $fn = 16) offset(delta = -rr)
                square([rim_thickness, rim_width]);
}

module hub() {
    translate([0, 0, -hub_length / 2])
        cylinder(h = hub_length, d = hub_diameter);
}

module spokes() {
    for (i = [0 : spoke_count - 1])
        rotate([0, 0, spoke_phase + i * 360 / spoke_count])
            rotate([0, 90, 0])
                // from inside the hub to inside the rim
                translate([0, 0, hub_diameter / 4])
                    cylinder(h = r_in + rim_thickness / 2 - hub_diameter / 4,
                             d = spoke_diameter, $fn = max(12, $fn / 2));
}

module wheel_local() {
    difference() {
        union() { rim(); hub(); spokes(); }
        if (axle_diameter > 0)
            cylinder(h = hub_length + 2, d = axle_diameter, center = true);
    }
}

module wheel() {
    // stand upright: axle along y, lowest point at z = flat_depth, then cut
    // everything below z = 0 away to leave a flat contact patch
    big = 4 * R;
    intersection() {
        translate([0, 0, R - flat_depth]) rotate([90, 0, 0]) wheel_local();
        translate([-big / 2, -big / 2, 0]) cube(big);
    }
}

wheel();
