%DEMO
; DEMO: mills a rectangular boss (tool-centre path 80 x 50 mm, R10 corners)
; centred on part zero (G54): 3 roughing steps of 2 mm (clockwise, 0.5 mm
; stock left), then one finishing pass at full depth, counter-clockwise.
; Tool T1 = 10 mm end mill, top face of the stock is Z0.
G71 G90 G17
G54
T1 D1 M06
S3000 M03
G04 K0.5 ; let the spindle reach its speed
G00 Z50
G00 X-60 Y0
G00 Z5
P10 = 1200 ; contour feed in mm/min
$FOR P1 = 1, 3, 1
$IF P1==3
P10 = 800 ; last roughing step at full depth: slower
$ENDIF
G01 Z[-P1*2] F400
G01 X-40.5 Y0 FP10
G01 Y15
G02 X-30 Y25.5 I10.5 J0
G01 X30
G02 X40.5 Y15 I0 J-10.5
G01 Y-15
G02 X30 Y-25.5 I-10.5 J0
G01 X-30
G02 X-40.5 Y-15 I0 J10.5
G01 Y0
G01 X-60
G00 Z5
$ENDFOR
; finishing pass at Z-6, counter-clockwise, tool-centre path 80 x 50 mm
G01 Z-6 F400
G01 X-40 Y0 F600
G01 Y-15
G03 X-30 Y-25 I10 J0
G01 X30
G03 X40 Y-15 I0 J10
G01 Y15
G03 X30 Y25 I-10 J0
G01 X-30
G03 X-40 Y15 I0 J-10
G01 Y0
G01 X-60
G00 Z50
M05
M30
