// clever-support CAD corpus: a threaded rod standing on the bed, M3 x 0.5 (the tests scale it
// 4x, to M12 x 2). The thread is a trapezoidal ISO-like profile: flanks at 30 degrees from the
// horizontal (the lower flank is an overhang all the way round), a flat crest and root.
// Made as one twisted extrusion of a "snail" section (radius a function of angle), so it needs
// no boolean: the section at height z is the profile at phase (angle - 360 z / pitch).
// Units: mm. Base flat on z = 0. Same licence as the clever-support project.

pitch = 0.5;
major = 3.0;
depth = 0.6 * pitch;         // thread depth (radial), about ISO's 0.613 pitch
length = 3;
steps = 64;                  // section corners per turn
slices_per_turn = 32;

// Radius at phase t in [0, 1) of one pitch: root, rising flank, crest, falling flank.
function radius_at(t) =
    let (r0 = major / 2 - depth, flank = depth * tan(30) / pitch)  // share of the pitch per flank
    t < 0.5 - flank ? r0 :
    t < 0.5 ? r0 + depth * (t - (0.5 - flank)) / flank :
    t < 1 - flank ? r0 + depth :
    r0 + depth * (1 - (t - (1 - flank)) / flank);

section = [for (i = [0 : steps - 1]) let (a = 360 * i / steps, r = radius_at(i / steps)) [r * cos(a), r * sin(a)]];

linear_extrude(height = length, twist = -360 * length / pitch, slices = slices_per_turn * length / pitch)
    polygon(section);
