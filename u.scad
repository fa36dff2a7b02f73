use <nolib.scad> cube(1);
