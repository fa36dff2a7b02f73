// clever-support example: simple bird on a perch plate
// Echoes the "bird" model of Vanek et al., "Clever Support", SGP 2014.
// An ellipsoid body with a head, a conical beak and a flat tail stands on
// two thin legs on a small base plate; the wings are stretched out
// sideways.  Overhangs: the undersides of the wings, body, head, beak and
// tail; only the thin legs connect the bird to the plate.
// Units: mm.  The bird looks along +x, wings along y.  Base is flat on z = 0.
// Same licence as the clever-support project.

/* [Body] */
// Body length (mm)
body_length = 32;        // [20:1:45]
// Body width (mm)
body_width = 18;         // [10:1:30]
// Body height (mm)
body_height = 18;        // [10:1:30]
// Height of the body centre above the bed (mm)
body_z = 28;             // [15:1:45]

/* [Head] */
// Head diameter (mm)
head_diameter = 14;      // [8:1:20]
// Beak length (mm)
beak_length = 9;         // [4:1:16]
// Beak base diameter (mm)
beak_diameter = 6;       // [3:0.5:10]

/* [Wings] */
// Wing span, tip to tip (mm)
wing_span = 76;          // [40:1:80]
// Wing chord (front-to-back width) (mm)
wing_chord = 16;         // [8:1:26]
// Wing thickness at the root (mm)
wing_thickness = 4;      // [2:0.5:8]
// Dihedral: upward tilt of the wings (deg)
wing_dihedral = 12;      // [0:1:35]

/* [Tail] */
// Tail length behind the body (mm)
tail_length = 14;        // [6:1:22]
// Tail tilt upwards (deg)
tail_tilt = 15;          // [0:1:40]

/* [Legs and plate] */
// Leg diameter (mm)
leg_diameter = 3;        // [1.5:0.1:5]
// Distance between the legs (mm)
leg_spacing = 8;         // [4:0.5:14]
// Base plate size x, y (mm)
plate_size = [26, 18];   // [10:1:40]
// Base plate thickness (mm)
plate_thickness = 2;     // [1:0.5:5]

/* [Resolution] */
// Facets on full circles
$fn = 32;                // [16:4:64]

// ---------------------------------------------------------------------------
body_c = [0, 0, body_z];
head_c = body_c + [0.45 * body_length, 0, 0.45 * body_height + 0.2 * head_diameter];

module ellipsoid(size) {
    scale(size / 2) sphere(r = 1);
}

module body() {
    translate(body_c) rotate([0, -10, 0])
        ellipsoid([body_length, body_width, body_height]);
}

module head() {
    translate(head_c) sphere(d = head_diameter);
    // beak: cone pointing forward, slightly downward
    translate(head_c + [0.35 * head_diameter, 0, -0.05 * head_diameter])
        rotate([0, 95, 0])
            cylinder(h = beak_length + 0.15 * head_diameter,
                     d1 = beak_diameter, d2 = 0.6);
}

// One wing as a flattened ellipsoid from the body's mid-line outwards.
// side = +1 (left, +y) or -1 (right, -y).
module wing(side) {
    half = wing_span / 2;
    translate(body_c + [0, 0, 0.15 * body_height])
        rotate([side * wing_dihedral, 0, 0])
            translate([0, side * half / 2, 0])
                // sweep the wing back a little
                rotate([0, 0, -side * 8])
                    ellipsoid([wing_chord, half, wing_thickness]);
}

module tail() {
    translate(body_c + [-0.4 * body_length, 0, 0])
        rotate([0, -tail_tilt, 0])
            translate([-tail_length / 2, 0, 0])
                ellipsoid([tail_length + 0.3 * body_length, 0.7 * body_width,
                           0.2 * body_height]);
}

module legs() {
    // from inside the plate up into the body
    for (s = [-1, 1])
        translate([0, s * leg_spacing / 2, plate_thickness / 2])
            cylinder(h = body_z - plate_thickness / 2, d = leg_diameter,
                     $fn = 16);
}

module plate() {
    translate([-plate_size[0] / 2, -plate_size[1] / 2, 0])
        cube([plate_size[0], plate_size[1], plate_thickness]);
}

module bird() {
    union() {
        plate();
        legs();
        body();
        head();
        wing(1);
        wing(-1);
        tail();
    }
}

bird();
