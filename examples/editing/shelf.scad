// A small table with a shelf, for the "Editing supports by hand" walk-through in README.md.
// `width` is the table's width (mm): clever-support shelf.scad -D width=50
width = 40;
depth = 20;
leg = 4;
cube([leg, depth, 30]);                                     // left leg
translate([width - leg, 0, 0]) cube([leg, depth, 30]);      // right leg
translate([0, 0, 30]) cube([width, depth, 3]);              // table top
translate([leg, 0, 12]) cube([width - 2 * leg, depth, 2]);  // shelf between the legs
