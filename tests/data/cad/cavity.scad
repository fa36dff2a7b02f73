// clever-support CAD corpus: a block with a closed cavity inside (a sealed pocket: its ceiling is
// an overhang that only the model's own floor under it can carry), and a blind pocket open to the
// side with a 1.4 mm high mouth.
// Units: mm. Base flat on z = 0. Same licence as the clever-support project.

difference() {
    cube([24, 16, 14]);
    translate([3, 3, 3]) cube([10, 10, 6]);          // sealed cavity, 6 mm high
    translate([16, -1, 5]) cube([5, 10, 1.4]);       // blind slot from the front
}
