// A wall hook: a back plate with two screw holes and an arm curving up.
plate_w = 20;
plate_h = 50;
plate_t = 4;
arm_l = 30;
hole_d = 4;
$fn = 40;
difference() {
    cube([plate_w, plate_t, plate_h]);
    for (z = [12, plate_h - 12])
        translate([plate_w / 2, -1, z]) rotate([-90, 0, 0]) cylinder(d = hole_d, h = plate_t + 2);
}
translate([0, 0, 0]) cube([plate_w, arm_l, plate_t]);
translate([0, arm_l - plate_t, 0]) cube([plate_w, plate_t, 15]);
