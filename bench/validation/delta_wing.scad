// Validation part (bench/validation): a delta wing held over the bed by its root block.
// Exercises: a flat roof with diagonal rims. A triangular plate (60 mm long, 50 mm wide at its root,
// 6 mm at its tip) 1.6 mm thick, tilted 8 deg about its length, 5 mm over the bed at its middle;
// its underside is a sloping ceiling whose two leading edges run diagonally to any rows along or
// across it. Units: mm. Written 2026-12-06; never used to tune the generator (see bench/README.md).

/* [Wing] */
// Length from root to tip (mm)
length = 60;            // [30:1:120]
// Span at the root and at the tip (mm)
span = [50, 6];
// Plate thickness (mm)
plate_t = 1.6;          // [0.8:0.2:4]
// Height of the plate's middle over the bed (mm)
height = 5;             // [2:0.5:20]
// Tilt about its length (deg)
tilt = 8;               // [0:1:30]

/* [Root block] */
// Root block: length, width, height (mm)
block = [8, 16, 9];

union() {
    translate([0, 0, height]) rotate([tilt, 0, 0])
        linear_extrude(plate_t)
            polygon([[0, -span[0] / 2], [0, span[0] / 2], [length, span[1] / 2], [length, -span[1] / 2]]);
    translate([-block[0] + 2, -block[1] / 2, 0]) cube(block);
}
