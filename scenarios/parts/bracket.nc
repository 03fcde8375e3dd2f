(A bracket's outline, 200 x 350 mm, corners rounded to 30 mm, a relief 20 mm deep on its)
(right side with 10 mm fillets; tangent everywhere. In the part's frame, millimetres,)
(counter-clockwise seen from +Z.)
N10 G21 G90 G17 G94
N20 G0 X30 Y0 Z5          (above the start)
N30 G0 Z0                 (down to the edge: the contour starts here)
N40 G1 X170 F6000         (6 m/min = 100 mm/s along the outline)
N50 G3 X200 Y30 I0 J30
N60 G1 Y150
N70 G3 X190 Y160 I-10 J0 F1800 (into the relief at 30 mm/s)
N80 G2 X180 Y170 I0 J10
N90 G1 Y180
N100 G2 X190 Y190 I10 J0  (out of it)
N110 G3 X200 Y200 I0 J10
N120 G1 Y320 F6000
N130 G3 X170 Y350 I-30 J0
N140 G1 X30
N150 G3 X0 Y320 I0 J-30
N160 G1 Y30
N170 G3 X30 Y0 I30 J0
N180 G0 Z5                (retract: not part of the contour)
N190 M30
