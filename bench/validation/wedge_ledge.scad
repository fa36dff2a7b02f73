// Validation part (bench/validation): a wall with two ledges.
// Exercises: flat roofs with diagonal rims over the bed. A standing wall carries, on one side, a
// wedge-shaped ledge 7 mm up that tapers from 30 mm deep to 6 mm over the wall's 50 mm, and on the
// other a triangular shelf 12 mm up. Units: mm. Written 2026-12-06; never used to tune the generator
// (see bench/README.md).

/* [Wall] */
// Wall length, thickness, height (mm)
wall = [50, 4, 20];

/* [Wedge ledge] */
// Depth at the wall's two ends (mm)
wedge_depth = [30, 6];
// Height of its underside over the bed (mm)
wedge_z = 7;            // [2:0.5:20]
// Thickness (mm)
wedge_t = 2;            // [1:0.5:5]

/* [Triangular shelf] */
// Depth at its apex (mm)
shelf_depth = 20;       // [5:1:40]
// Height of its underside over the bed (mm)
shelf_z = 12;           // [2:0.5:20]
// Thickness (mm)
shelf_t = 2;            // [1:0.5:5]

union() {
    cube(wall);
    translate([0, wall[1], wedge_z])
        linear_extrude(wedge_t) polygon([[0, 0], [wall[0], 0], [wall[0], wedge_depth[1]], [0, wedge_depth[0]]]);
    translate([0, 0, shelf_z]) mirror([0, 1, 0])
        linear_extrude(shelf_t) polygon([[5, 0], [wall[0] - 5, 0], [wall[0] / 2, shelf_depth]]);
}
