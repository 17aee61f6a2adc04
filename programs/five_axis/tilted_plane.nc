%TILTED
; 3+2 machining in a plane tilted 30 degrees about X, on a rotary-table AC machine
; (machines/five_axis_ac.toml).  #TOOL ORI tilts the table so that the tool is perpendicular to the
; plane; two holes are drilled with G01 plunges and a slot is milled with G42 in the plane.
N10 G90 G17 G94 G71
N20 #CS NEW [1] [MODE 1, 0, 0, 20, 30, 0, 0]   ; the plane: 20 above the part zero, turned 30 deg about X
N30 T1 D1 M6                                     ; 5 mm drill, 80 long
N40 S3000 M3
N50 #TOOL ORI                                    ; the table turns during the next move
N60 G0 X60 Y20 Z3
N70 G1 G91 Z-13 F300
N80 G0 Z13
N90 G90 X120
N100 G1 G91 Z-13
N110 G0 Z13
N120 G90 Z40
N130 T2 D1 M6                                    ; 6 mm end mill, 60 long
N140 S8000 M3
N150 G0 X10 Y60 Z5
N160 G1 Z-2 F400
N170 G42 G1 X20 Y60                              ; the slot's right wall, 3 mm from the line Y60
N180 X100
N190 G40 G1 X110
N200 G0 Z40
N210 #CS OFF
N220 G0 A0 C0
N230 M30
