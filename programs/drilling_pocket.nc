%DRLPOCK
; Drilling and pocketing demo: canned cycles of the 8060/8065 milling model.
; A 120 x 80 plate, part zero at its lower left corner, top face Z0.
; The tool radii are written here (V.TM.TOR) so the demo runs on the default machine;
; on a real machine they come from the tool table.
N10 G71 G90 G17 G94
N15 G40
; ---- centre drill, then 8 mm drill: a row of holes and a bolt circle
N20 T1 D1 M06
N25 V.TM.TOR=4
N30 S1800 M03
N35 G0 X15 Y15
N40 G0 Z30
N45 G98 G81 X15 Y15 Z2 I-12 F180        ; first hole of the row
N50 G160 A0 X90 K4                      ; three more, 30 mm apart (X = row length, K = holes)
N55 G99 G83 X60 Y60 Z2 I-5 J3 F150      ; deep hole in the centre of the bolt circle
N60 G81 X80 Y60 Z2 I-10                 ; first hole of the circle (G99: return to Z2)
N65 G163 X-20 Y0 K6                     ; five more, on a circle of radius 20 around X60 Y60
N70 G80
; ---- rigid tapping M10 x 1.5 of the row
N75 T2 D1 M06
N80 S500 M03
N85 G0 X15 Y15 Z30
N90 G98 G84 X15 Y15 Z3 I-10 R1 F750     ; pitch 750/500 = 1.5
N95 G160 X90 I30
N100 G80
; ---- end mill: a rectangular pocket and a circular pocket
N105 T3 D1 M06
N110 V.TM.TOR=5
N115 S3000 M03
N120 G0 X35 Y55 Z30
N125 G98 G87 X30 Y60 Z2 I-6 J14 K9 B3 C7 L0.5 H400 V150 F600
N130 G88 X95 Y25 Z2 I-8 J-12 B4 C7 L0.5 H400 F600
N135 G80
; ---- thread mill: an M26 x 1.5 inside thread in the circular pocket (its wall is the minor diameter)
N136 T4 D1 M06
N137 V.TM.TOR=5
N138 S2500 M03
N139 G0 X95 Y25 Z30
N140 G98 G211 Z1.5 I-7.5 J13 K1 B1.5 F300  ; major radius 13, depth 1, 6 turns (provisional: CYC020)
N141 G80
N142 G0 Z100
N145 M05
N150 M30
