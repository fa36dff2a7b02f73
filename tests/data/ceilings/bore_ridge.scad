// A bearing housing: a 50 x 24 x 26 mm block with a 14 mm bore through it along x, its axis 13 mm
// over the bed (tests/unit/test_ceilings.cpp). With $fn = 48 the bore's crown and floor are ridges
// (a vertex of the polygon at the top and at the bottom): the crown's edge samples lie level along
// the ridge, with the nearly level facets beside the floor's ridge under them, where walls could
// stand; the crown's sloping sides have no level floor under them and go to the tree.
// bore_ridge.stl is this file as OpenSCAD 2021.01 exports it by default (ASCII STL, 6 significant
// digits), kept as written: the binary export's float32 vertices sample a little differently and
// did not show the fault that test pins down.
// Units: mm. Base flat on z = 0. Same licence as the clever-support project.
difference() {
    translate([-25, -12, 0]) cube([50, 24, 26]);
    translate([-30, 0, 13]) rotate([0, 90, 0]) cylinder(d = 14, h = 60, $fn = 48);
}
