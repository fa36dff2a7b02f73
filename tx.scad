linear_extrude(1) text("hi");
