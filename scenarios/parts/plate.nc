(A plate's outline, 160 x 100 mm, straight edges meeting at sharp corners: one corner)
(chamfered 20 mm and a V notch 15 mm deep in the top edge. G64 P0.5 blends every corner)
(by the arc that leaves it by 0.5 mm at most. In the part's frame, millimetres,)
(counter-clockwise seen from +Z.)
N10 G21 G90 G17 G94 G64 P0.5
N20 G0 X0 Y0 Z5           (above the start)
N30 G0 Z0                 (down to the edge: the contour starts here)
N40 G1 X160 F3000         (50 mm/s along the edges)
N50 G1 Y80
N60 G1 X140 Y100          (the chamfer)
N70 G1 X95
N80 G1 X80 Y85 F1200      (into the notch at 20 mm/s)
N90 G1 X65 Y100
N100 G1 X0 F3000
N110 G1 Y0
N120 G0 Z5                (retract: not part of the contour)
N130 M30
