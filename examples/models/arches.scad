// clever-support example: arcade with arches of different spans + a lintel
// Echoes the "arches" model of Vanek et al., "Clever Support", SGP 2014.
// A wall standing on the bed is pierced by (left to right) a wide
// semicircular arch, a narrower semicircular arch, a flat segmental arch
// and a rectangular doorway with a flat lintel.  The crowns of the arches
// and the whole lintel underside are (near-)horizontal overhangs; a
// projecting cornice along the top adds an overhanging ledge.
// Units: mm.  Base is flat on z = 0.
// Same licence as the clever-support project.

/* [Wall] */
// Height of the wall without cornice (mm)
wall_height = 42;        // [25:1:60]
// Wall thickness (mm)
wall_depth = 10;         // [4:1:20]
// Width of the piers between the openings (mm)
pier_width = 4.5;        // [3:0.5:10]

/* [Openings] */
// Span of the wide semicircular arch (mm)
span_wide = 20;          // [10:1:30]
// Span of the narrow semicircular arch (mm)
span_narrow = 12;        // [6:1:20]
// Span of the flat segmental arch (mm)
span_segmental = 12;     // [6:1:20]
// Rise of the segmental arch above its springing line (mm)
rise_segmental = 3;      // [1:0.5:6]
// Span of the rectangular doorway under the flat lintel (mm)
span_lintel = 8;         // [4:1:16]
// Height of the springing line (where the arches start) above the bed (mm)
spring_height = 16;      // [6:1:30]
// Height of the top of the lintel doorway (mm)
lintel_height = 26;      // [10:1:40]

/* [Cornice] */
// How far the cornice projects from each wall face (mm)
cornice_overhang = 2;    // [0:0.5:5]
// Cornice thickness (mm)
cornice_height = 3;      // [1:0.5:6]

/* [Resolution] */
// Facets on full circles
$fn = 48;                // [16:4:96]

// ---------------------------------------------------------------------------
spans = [span_wide, span_narrow, span_segmental, span_lintel];

// sum of the first n entries of v
function partial_sum(v, n) = n <= 0 ? 0 : v[n - 1] + partial_sum(v, n - 1);

// piers at both ends and between all openings
total_length = partial_sum(spans, len(spans)) + (len(spans) + 1) * pier_width;
// x of the left edge of opening i
function opening_x(i) = pier_width * (i + 1) + partial_sum(spans, i);

eps = 0.01;   // makes the cutters poke through the wall faces

// 2D opening profiles in the x/z plane, left edge at x = 0, sill at z = -1
// (below the bed, so the openings go right down to the ground).
module semicircular_profile(span) {
    translate([0, -1]) square([span, spring_height + 1]);
    translate([span / 2, spring_height]) circle(d = span);
}

module segmental_profile(span, rise) {
    // circle through both springing points and the crown
    R = (span * span / 4 + rise * rise) / (2 * rise);
    translate([0, -1]) square([span, spring_height + 1]);
    intersection() {
        translate([span / 2, spring_height + rise - R]) circle(r = R, $fn = 4 * $fn);
        translate([0, spring_height - eps]) square([span, rise + 2 * eps]);
    }
}

module lintel_profile(span) {
    translate([0, -1]) square([span, lintel_height + 1]);
}

// Extrude a profile drawn in x/z through the wall (along y).
module through_wall() {
    translate([0, wall_depth + 1, 0]) rotate([90, 0, 0])
        linear_extrude(height = wall_depth + 2) children();
}

module arches() {
    difference() {
        union() {
            cube([total_length, wall_depth, wall_height]);
            // cornice
            translate([-cornice_overhang, -cornice_overhang,
                       wall_height - cornice_height])
                cube([total_length + 2 * cornice_overhang,
                      wall_depth + 2 * cornice_overhang, cornice_height]);
        }
        through_wall() {
            translate([opening_x(0), 0]) semicircular_profile(span_wide);
            translate([opening_x(1), 0]) semicircular_profile(span_narrow);
            translate([opening_x(2), 0])
                segmental_profile(span_segmental, rise_segmental);
            translate([opening_x(3), 0]) lintel_profile(span_lintel);
        }
    }
}

arches();
