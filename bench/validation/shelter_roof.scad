// Validation part (bench/validation): a shelter, a roof over a bench.
// Exercises: a roof over the model. A flat 40 x 24 mm roof on two back posts
// overhangs a bench; under the bench's footprint the roof's supports stand on
// the bench seat (model contacts), elsewhere they go down to the bed. The
// seat's own front lip is a small ledge, and the roof's front edge has a
// sloped fascia (a 45 deg chamfer) that needs no support.
// Units: mm. Never used to tune the generator (see bench/README.md).

/* [Roof] */
// Roof size (mm)
roof = [44, 26];          // [x, y]
// Roof height above the bed (underside, mm)
roof_z = 30;              // [15:1:50]
// Roof thickness (mm)
roof_t = 2.4;             // [1.2:0.2:5]
// Back post size (mm)
post = 4;                 // [2:0.5:8]

/* [Bench] */
// Seat height (mm)
seat_z = 10;              // [4:1:20]
// Seat size (mm)
seat = [30, 9];           // [x, y]
// Seat thickness (mm)
seat_t = 2;               // [1:0.5:4]
// Lip under the seat's front edge (mm)
lip = 1.5;                // [0:0.5:3]

module shelter() {
    // back wall with two posts as its ends, roof on top
    for (x = [0, roof[0] - post]) translate([x, roof[1] - post, 0]) cube([post, post, roof_z]);
    translate([0, roof[1] - 1.6, 0]) cube([roof[0], 1.6, roof_z * 0.4]);   // low back wall
    translate([0, 0, roof_z]) cube([roof[0], roof[1], roof_t]);
    // fascia along the front: a 45 deg chamfer down from the roof
    translate([0, 0, roof_z]) rotate([0, 90, 0]) linear_extrude(height = roof[0])
        polygon([[0, 0], [3, 0], [0, 3]]);
}

module bench() {
    x0 = (roof[0] - seat[0]) / 2;
    y0 = 6;
    translate([x0, y0, seat_z - seat_t]) cube([seat[0], seat[1], seat_t]);
    translate([x0, y0 - lip, seat_z - seat_t]) cube([seat[0], lip, seat_t / 2]);  // thin front lip
    for (x = [x0 + 2, x0 + seat[0] - 5]) translate([x, y0 + 2, 0]) cube([3, seat[1] - 4, seat_z - seat_t]);
}

shelter();
bench();
