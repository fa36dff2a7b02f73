// Validation part (bench/validation): a wall rack with hooks and a shelf lip,
// printed standing as it hangs on the wall.
// Exercises: hooks and a roof over the model. A back plate stands on its lower
// edge; three J-hooks stick out of it (round horizontal arms turning up at the
// end: a round ceiling under each arm), and above them a small shelf with a
// raised lip at its front, whose flat underside is a roof over the hooks: its
// supports land on the hooks or pass beside them to the bed. Two keyhole slots
// for hanging are cut through the plate (flat-topped horizontal holes).
// Units: mm. Never used to tune the generator (see bench/README.md).

/* [Plate] */
// Back plate width and height (mm)
plate = [70, 55];       // [w, h]
// Plate thickness (mm)
plate_t = 4;            // [2:0.5:8]

/* [Hooks] */
// Number of hooks
hooks = 3;              // [1:1:6]
// Hook arm diameter (mm)
hook_d = 5;             // [3:0.5:10]
// How far the hook reaches out (mm)
hook_out = 18;          // [8:1:40]
// Height of the upturned end (mm)
hook_up = 7;            // [3:1:15]
// Height of the hook arms above the bed (mm)
hook_z = 12;            // [6:1:40]

/* [Shelf] */
// Shelf depth (mm)
shelf_d = 24;           // [10:1:40]
// Shelf thickness (mm)
shelf_t = 2.5;          // [1.5:0.5:5]
// Lip height (mm)
lip_h = 5;              // [0:0.5:10]
// Shelf height above the bed (underside, mm)
shelf_z = 38;           // [20:1:60]

/* [Resolution] */
$fn = 32;               // [16:4:96]

module hook() {
    // arm out along +y, rounded elbow, upturned end
    rotate([-90, 0, 0]) cylinder(d = hook_d, h = hook_out);
    translate([0, hook_out, 0]) sphere(d = hook_d);
    translate([0, hook_out, 0]) cylinder(d = hook_d, h = hook_up);
    translate([0, hook_out, hook_up]) sphere(d = hook_d);
}

module keyhole() {
    // round head over a slot, through the plate along y
    rotate([-90, 0, 0]) translate([0, 0, -1]) cylinder(d = 8, h = plate_t + 2);
    translate([-2, -1, 0]) cube([4, plate_t + 2, 8]);
}

module rack() {
    difference() {
        translate([-plate[0] / 2, -plate_t, 0]) cube([plate[0], plate_t, plate[1]]);
        for (x = [-plate[0] / 3, plate[0] / 3]) translate([x, -plate_t, plate[1] - 14]) keyhole();
    }
    for (i = [0:hooks - 1]) translate([(i - (hooks - 1) / 2) * plate[0] / hooks, -0.5, hook_z]) hook();
    translate([-plate[0] / 2, 0, shelf_z]) cube([plate[0], shelf_d, shelf_t]);
    translate([-plate[0] / 2, shelf_d - 2, shelf_z]) cube([plate[0], 2, shelf_t + lip_h]);
}

rack();
