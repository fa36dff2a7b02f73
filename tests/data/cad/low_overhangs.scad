// clever-support CAD corpus: low overhangs. Ledges hang a little above a floor or above a lower
// step whose edge lies somewhere under the ledge: the tip under the ledge has the step beside it.
// Units: mm. Base flat on z = 0. Same licence as the clever-support project.

clearances = [0.4, 0.7, 1.0, 1.4, 1.9, 2.5, 3.2, 4.0];  // ledge underside above the floor below it
step_offsets = [0.3, 1.2];  // how far the lower step's edge reaches under the ledge (along y)
floor_z = 3;     // top of the base under the ledges
step_h = 1.2;    // a lower step on the floor
ledge = [8, 6, 2];  // width, reach, thickness

module bay(c, off, stepped) {
    // back wall carrying the ledge
    cube([ledge[0], 3, floor_z + c + ledge[2] + 2]);
    // base
    translate([0, -10, 0]) cube([ledge[0], 13, floor_z]);
    // the ledge, underside at floor_z + c
    translate([0, 3 - 0.01 - ledge[1], floor_z + c]) cube([ledge[0], ledge[1] + 0.01, ledge[2]]);
    // a step on the floor whose edge lies `off` under the ledge's front edge
    if (stepped)
        translate([0, -10, floor_z - 0.01]) cube([ledge[0], 13 - ledge[1] + off, step_h + 0.01]);
}

for (i = [0 : len(clearances) - 1], j = [0 : 2])
    translate([i * (ledge[0] + 1), j * 15, 0])
        bay(clearances[i] + (j > 0 ? step_h : 0), step_offsets[max(j - 1, 0)], j > 0);
