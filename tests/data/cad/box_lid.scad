// clever-support CAD corpus: an open box with a lid lip. A flange sticks out round the top of the
// box (an overhang ledge, 1.5 mm wide, 1 mm thick) and an inner lip stands in from the walls just
// below the rim (the ledge a lid rests on); the box floor is raised on four short feet, so its
// underside hangs 0.8 mm above the bed between them.
// Units: mm. Base flat on z = 0. Same licence as the clever-support project.

outer = [30, 22, 16];
wall = 1.6;
floor_t = 1.6;
feet_h = 0.8;
flange = [1.5, 1.0];   // reach, thickness
lip = [1.2, 1.0, 2.5]; // reach inward, thickness, depth below the rim

translate([0, 0, feet_h]) difference() {
    union() {
        cube(outer);
        translate([-flange[0], -flange[0], outer[2] - flange[1]])
            cube([outer[0] + 2 * flange[0], outer[1] + 2 * flange[0], flange[1]]);
    }
    difference() {
        translate([wall, wall, floor_t]) cube([outer[0] - 2 * wall, outer[1] - 2 * wall, outer[2]]);
        // the inner lip is left standing
        translate([0, 0, outer[2] - lip[2] - lip[1]]) difference() {
            cube([outer[0], outer[1], lip[1]]);
            translate([wall + lip[0], wall + lip[0], -1])
                cube([outer[0] - 2 * (wall + lip[0]), outer[1] - 2 * (wall + lip[0]), lip[1] + 2]);
        }
    }
}
for (x = [0, outer[0] - 4], y = [0, outer[1] - 4]) translate([x, y, 0]) cube([4, 4, feet_h + 0.01]);
