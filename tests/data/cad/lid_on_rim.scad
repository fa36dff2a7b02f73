// clever-support CAD corpus: a lid lying top up on its locating rim, as an enclosure's lid is
// printed without turning it over. A 40 x 30 x 2 mm plate 3 mm over the bed rests on a 1.2 mm
// frame inset 2.2 mm from its edges: its underside is a flat roof low over the bed, and a 2.2 mm
// lip runs round the frame outside it.
// Units: mm. Base flat on z = 0. Same licence as the clever-support project.

plate = [40, 30, 2];
rim_h = 3;
inset = 2.2;
frame = 1.2;

translate([-plate[0] / 2, -plate[1] / 2, 0]) {
    translate([0, 0, rim_h]) cube(plate);
    translate([inset, inset, 0]) difference() {
        cube([plate[0] - 2 * inset, plate[1] - 2 * inset, rim_h + 0.01]);
        translate([frame, frame, -1]) cube([plate[0] - 2 * inset - 2 * frame, plate[1] - 2 * inset - 2 * frame, rim_h + 2]);
    }
}
