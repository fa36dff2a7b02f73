// clever-support CAD corpus: slots that are slightly tilted (ceiling and floor sloping by a few
// degrees along the slot and across it), heights 0.3 to 3 mm.
// Units: mm. Base flat on z = 0. Same licence as the clever-support project.

heights = [0.3, 0.7, 1.1, 1.6, 2.2, 3.0];
tilts = [[3, 0], [0, 6], [-4, 2]];  // rotation about x and y of the slot, degrees
block = [10, 10, 14];
slot_z = 7;

module block_with_slot(h, t) {
    difference() {
        cube(block);
        translate([block[0] / 2, 2, slot_z + h / 2])
            rotate([t[0], t[1], 0]) translate([-3.5, -4, -h / 2]) cube([7, 9, h]);
    }
}

for (i = [0 : len(heights) - 1], j = [0 : len(tilts) - 1])
    translate([i * (block[0] + 1), j * (block[1] + 1), 0]) block_with_slot(heights[i], tilts[j]);
