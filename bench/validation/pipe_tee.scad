// Validation part (bench/validation): a flanged pipe tee lying on its side.
// Exercises: round ceilings. The run and the branch lie horizontally, so the
// top half of every bore is a ceiling of growing slope (flat at the crown),
// low over the bed inside the pipe and over the pipe's own floor. The flanges
// are wider than the pipe: the part rests on the flange rims, and the pipe's
// underside is a round roof a few mm over the bed between them.
// Units: mm. Never used to tune the generator (see bench/README.md).

/* [Pipe] */
// Outer diameter of the pipe (mm)
pipe_od = 20;          // [10:1:40]
// Bore diameter (mm)
pipe_bore = 14;        // [6:1:34]
// Length of the run, flange face to flange face (mm)
run_length = 70;       // [40:1:120]
// Length of the branch from the run's axis to its flange face (mm)
branch_length = 38;    // [25:1:80]

/* [Flanges] */
// Flange diameter (mm)
flange_d = 32;         // [14:1:60]
// Flange thickness (mm)
flange_t = 4;          // [2:0.5:8]
// Bolt holes per flange
bolts = 4;             // [3:1:8]
// Bolt hole diameter (mm)
bolt_d = 3.4;          // [2:0.1:6]

/* [Resolution] */
$fn = 48;              // [16:4:96]

eps = 0.01;

// A pipe of length l along +z from z = 0 with a flange at its far end.
module flanged_pipe(l) {
    difference() {
        union() {
            cylinder(d = pipe_od, h = l);
            translate([0, 0, l - flange_t]) cylinder(d = flange_d, h = flange_t);
        }
        for (i = [0:bolts - 1])
            rotate([0, 0, 360 * (i + 0.5) / bolts])
                translate([(flange_d + pipe_od) / 4, 0, l - flange_t - eps])
                    cylinder(d = bolt_d, h = flange_t + 2 * eps, $fn = 16);
    }
}

module bore(l) { translate([0, 0, -eps]) cylinder(d = pipe_bore, h = l + 2 * eps); }

module tee() {
    difference() {
        union() {
            // run along x, centred; branch along +y
            rotate([0, 90, 0]) flanged_pipe(run_length / 2);
            rotate([0, -90, 0]) flanged_pipe(run_length / 2);
            rotate([-90, 0, 0]) flanged_pipe(branch_length);
        }
        rotate([0, 90, 0]) bore(run_length / 2);
        rotate([0, -90, 0]) bore(run_length / 2);
        rotate([-90, 0, 0]) bore(branch_length);
    }
}

// lying on its side: lowest point (the flange rims) on the bed
translate([0, 0, flange_d / 2]) tee();
