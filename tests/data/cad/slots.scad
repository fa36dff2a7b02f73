// clever-support CAD corpus: horizontal slots of every height from 0.2 mm to 3 mm.
// A row of blocks standing on the bed; each is cut by one slot from the front (-y) side,
// 6 mm deep. The slot ceiling is a flat overhang a few tenths to a few millimetres above the
// slot floor. Every other slot has a groove in its floor (a lower step under the ceiling, the
// gearbox housing of issue #12: the floor under a sample is not the floor under its footprint).
// Units: mm. Base flat on z = 0. Same licence as the clever-support project.

heights = [0.2, 0.4, 0.6, 0.8, 1.0, 1.1, 1.2, 1.5, 2.0, 2.4, 2.6, 3.0];
block = [9, 10, 14];   // each block
slot_z = 8;            // slot floor above the bed
slot_depth = 6;        // how far the slot reaches into the block (from -y)
slot_width = 7;        // along x
groove = [2.6, 1.1];   // groove in the floor: width (along y), depth

module block_with_slot(h, grooved) {
    difference() {
        cube(block);
        translate([(block[0] - slot_width) / 2, -1, slot_z]) cube([slot_width, slot_depth + 1, h]);
        if (grooved)
            translate([(block[0] - slot_width) / 2, 2, slot_z - groove[1]])
                cube([slot_width, groove[0], groove[1] + 0.01]);
    }
}

for (i = [0 : len(heights) - 1])
    translate([i * (block[0] + 1), 0, 0]) block_with_slot(heights[i], i % 2 == 1);
