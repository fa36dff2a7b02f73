// clever-support CAD corpus: a tunnel through a block standing on the bed, its axis 30 degrees
// from x. The tunnel's round ceiling (crown 8.5 mm up) is level along 30 degrees: rows of walls
// along x or y would cross its curve as a staircase of short pieces.
// Units: mm. Base flat on z = 0. Same licence as the clever-support project.

rotate([0, 0, 30]) difference() {
    translate([-15, -10, 0]) cube([30, 20, 10]);
    translate([-16, 0, 2]) rotate([0, 90, 0]) cylinder(r = 6.5, h = 32, $fn = 64);
}
