// clever-support CAD corpus: a bracket. A base plate with an upright wall pierced by round holes
// of several diameters (their tops are round arches), two bosses standing out of the wall, ribs
// under a shelf, fillets where the shelf meets the wall, and a counterbored hole from below.
// Units: mm. Base flat on z = 0. Same licence as the clever-support project.

$fn = 40;
base = [60, 24, 3];
wall = [60, 4, 26];
holes = [1.5, 2.5, 4, 6, 9];   // diameters through the wall (axis along y)
shelf = [60, 10, 2.5];         // shelf sticking out of the wall's back, at shelf_z
shelf_z = 18;
fillet = 2.5;

module wall_with_holes() {
    difference() {
        translate([0, 8, 0]) cube(wall);
        for (i = [0 : len(holes) - 1])
            translate([6 + i * 11.5, 7, 9]) rotate([-90, 0, 0]) cylinder(d = holes[i], h = wall[1] + 2);
    }
}

module bosses() {
    for (x = [15, 45])
        translate([x, 8.01, 21]) rotate([90, 0, 0]) difference() {
            cylinder(d = 7, h = 6);
            translate([0, 0, -1]) cylinder(d = 3, h = 8);
        }
}

module shelf_with_ribs() {
    translate([0, 12 - 0.01, shelf_z]) cube(shelf);
    // ribs under the shelf: triangles from the wall out to the shelf's edge
    for (x = [5, 30, 55])
        translate([x - 1, 12 - 0.01, shelf_z + 0.01]) rotate([90, 0, 90])
            linear_extrude(2) polygon([[0, 0], [8, 0], [0, -8]]);
    // fillet under the shelf along the wall: a quarter-round filler
    translate([0, 12 - 0.01, shelf_z + 0.01]) rotate([0, 90, 0])
        difference() {
            translate([0, 0, 0]) cube([fillet, fillet, shelf[0]]);
            translate([fillet, fillet, -1]) cylinder(r = fillet, h = shelf[0] + 2);
        }
}

difference() {
    union() {
        cube(base);
        wall_with_holes();
        bosses();
        shelf_with_ribs();
    }
    // counterbored hole through the base from below: the counterbore's roof is an overhang
    translate([30, 3, -1]) cylinder(d = 3, h = 10);
    translate([30, 3, -1]) cylinder(d = 6, h = 2.5);
}
