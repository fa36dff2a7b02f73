// clever-support CAD corpus: overhangs one and two layers above the bed. A plate stands on a
// small pedestal so its underside is 0.2 mm (one layer) above the bed; a second plate hangs
// 0.4 mm above it, a third 1.0 mm.
// Units: mm. Base flat on z = 0. Same licence as the clever-support project.

for (i = [0 : 2]) {
    lift = [0.2, 0.4, 1.0][i];
    translate([i * 22, 0, 0]) {
        translate([7, 5, 0]) cube([6, 6, lift + 0.01]);
        translate([0, 0, lift]) cube([20, 16, 2]);
    }
}
