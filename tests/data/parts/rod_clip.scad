// A clip for a 12 mm rod: a C-shaped bore and two flange ears with 3.4 mm screw holes.
rod_d = 12;
wall = 3;
width = 10;
ear = 10;
hole_d = 3.4;
$fn = 48;
difference() {
    union() {
        cylinder(d = rod_d + 2 * wall, h = width);
        translate([-(rod_d / 2 + wall + ear), -wall / 2 - rod_d / 2 - wall + wall / 2, 0])
            cube([rod_d + 2 * wall + 2 * ear, wall, width]);
    }
    translate([0, 0, -1]) cylinder(d = rod_d, h = width + 2);
    translate([-rod_d / 2 + 1, 0, -1]) cube([rod_d - 2, rod_d, width + 2]);
    for (s = [-1, 1])
        translate([s * (rod_d / 2 + wall + ear / 2), 0, width / 2]) rotate([90, 0, 0]) cylinder(d = hole_d, h = 50, center = true);
}
