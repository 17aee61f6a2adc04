%RTCP5X
; #RTCP on a rotary-table AC machine (machines/five_axis_ac.toml): the program gives the tool tip in
; part coordinates and the table angles; the linear axes follow so that the tip stays on the path.
N10 G90 G17 G94 G71
N20 T2 D1 M6                       ; 6 mm end mill, 60 long
N30 S8000 M3
N40 #KIN ID [1]
N50 #RTCP ON
N60 G0 X0 Y0 Z50 A0 C0
N70 G1 Z5 F2000
N80 G1 X40 Y0 Z5 A-20 F1500        ; the tip runs along a line while the table tilts
N90 C90                            ; the table turns, the tip stays at the part point (40, 0, 5)
N100 X0 Y40 A0 C180                ; line and both axes together
N110 G0 Z50
N120 #RTCP OFF
N130 G0 A0 C0
N140 M30
