// Validation part (bench/validation): an overhang test piece.
// Exercises: ledges at several angles (measured from the vertical) sticking out
// of one wall, from printable without support (30 deg) to flat (90 deg), each
// a flat-bottomed or sloped ceiling of its own; and a flat roof low over the
// bed (a 30 x 20 mm table top 6 mm up, standing on two legs), the case where
// a slicer prints one zigzag per layer and a tree many small islands.
// Units: mm. Never used to tune the generator (see bench/README.md).

/* [Wall and ledges] */
// Wall height (mm)
wall_h = 40;                 // [20:1:60]
// Wall thickness (mm)
wall_t = 4;                  // [2:0.5:8]
// Ledge angles from the vertical (deg); 90 = flat underside
angles = [30, 45, 60, 75, 90];
// Width of each ledge along the wall (mm)
ledge_w = 10;                // [5:1:20]
// How far each ledge sticks out (mm)
ledge_out = 10;              // [4:1:20]
// Ledge thickness at its tip (mm)
ledge_tip = 2;               // [1:0.5:5]

/* [Low roof] */
// Height of the roof's underside above the bed (mm)
roof_gap = 6;                // [2:0.5:20]
// Roof size (mm)
roof_size = [30, 20];
// Roof thickness (mm)
roof_t = 2;                  // [1:0.5:5]
// Leg width (mm)
leg_w = 4;                   // [2:0.5:8]

ledge_pitch = ledge_w + 3;
wall_l = len(angles) * ledge_pitch + 3;

// A ledge whose underside leans `a` degrees from the vertical, out along +y.
module ledge(a) {
    drop = a >= 90 ? 0 : ledge_out / tan(a);   // how far the underside falls over its length
    top = 0;
    rotate([90, 0, 90]) linear_extrude(height = ledge_w)
        polygon([[0, top - drop - ledge_tip], [ledge_out, top - ledge_tip], [ledge_out, top], [0, top]]);
}

module test_wall() {
    cube([wall_l, wall_t, wall_h]);
    for (i = [0:len(angles) - 1]) {
        a = angles[i];
        drop = a >= 90 ? 0 : ledge_out / tan(a);
        // ledges step up the wall so each one's underside starts above the bed
        z = 8 + drop + ledge_tip + i * 5;
        translate([3 + i * ledge_pitch, wall_t, z]) ledge(a);
    }
}

module low_table() {
    translate([0, 0, roof_gap]) cube([roof_size[0], roof_size[1], roof_t]);
    for (x = [0, roof_size[0] - leg_w]) cube([leg_w, roof_size[1], roof_gap]);
}

test_wall();
translate([wall_l + 8, 0, 0]) low_table();
