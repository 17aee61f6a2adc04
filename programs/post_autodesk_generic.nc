%CAMGENERIC
; A program in the form Autodesk's generic "FAGOR 8058/8060/8065/8070" post writes it
; (the text forms it emits; see README "CAM posts").  It passes "fagorcnc check" with
; warnings only; "fagorcnc check --strict" refuses G51, G501/G500 and the lone G61.
; T3 D=10 CR=0 - ZMIN=-3 - FLAT END MILL
; T41 D=6 CR=0 - ZMIN=-3 - FLAT END MILL
G90 G94 G17
G71
G51 A45 E0.002
#MSG["OPT1: 2D Contour1"]
#DGWZ[-100,100,-100,100,-50,50]
#MCS G0 Z0
T3 D1 M6
T41
S9000 M3
M8
G54
G0 X-15 Y5
G0 Z5
P100=2400 ; CUTTING
P101=600 ; PLUNGE
G501 A60 E0.0024 J100 M1
G1 Z-3 FP101
G41 X-5 Y5 FP100
G3 X0 Y10 I0 J5
G1 Y20
G1 X40
G1 Y0
G1 X0
G1 Y10
G3 X-5 Y15 I-5 J0
G40 G1 X-15 Y15
G0 Z5
G500
M9
#MCS G0 Z0
#MCS G0 X0 Y0
#MSG[""]
G61
M5
M30
