%FLOW
; FLOW CONTROL DEMO, engraving 0.5 mm deep with a 3 mm cutter (tool centre):
; 1) a hexagon (R40) computed with COS/SIN in a $WHILE loop,
; 2) a radius table P11..P15 filled with indirect addressing in a $DO loop,
; 3) a five-pointed star at X100 that reads the table back,
; 4) three small shapes chosen by $SWITCH inside a $FOR loop,
; 5) a skipped optional pass ($GOTO N100),
; 6) a row of dots that stops at a radius limit ($IF ... $GOTO [DONE]).
G71 G90 G17 G54
T3 D1 M06
S8000 M03
G00 Z10
P0 = 0 ; P0 = 1 ends the dot row
;
; 1) HEXAGON: six edges, V.P.COUNT = number of edges already cut
V.P.COUNT = 0
P2 = 40
G00 XP2 Y0
G01 Z-0.5 F300
$WHILE V.P.COUNT < 6
V.P.COUNT = V.P.COUNT + 1 ; 1..6
P3 = V.P.COUNT * 60
P4 = P2 * COS[P3]
P5 = P2 * SIN[P3]
G01 XP4 YP5 F1200
$ENDWHILE
G00 Z5
;
; 2) RADIUS TABLE: P11 = 25, P12 = 27.07, P13 = 28.66, P14 = 30, P15 = 31.18
P1 = 10
$DO
P[P1+1] = 20 + SQRT[[P1-9]*25]
P1 += 1
$ENDDO P1 < 15
;
; 3) STAR CENTRED AT X100 Y0: outer points on the table radii, inner radius 12
P6 = 100
G00 X[P6+P11*COS[90]] Y[P11*SIN[90]]
G01 Z-0.5 F300
$FOR P7 = 0, 4, 1
P8 = 90 + P7*72 + 36
G01 X[P6+12*COS[P8]] Y[12*SIN[P8]] F1200
P8 = P8 + 36
P9 = P[11 + [P7+1] MOD 5]
G01 X[P6+P9*COS[P8]] Y[P9*SIN[P8]]
$ENDFOR
G00 Z5
;
; 4) SHAPES ON Y-80 AT X-60, X0, X60: 1 = SQUARE, 2 = CIRCLE R10, OTHER = CROSS
$FOR P16 = 1, 3, 1
P17 = -120 + P16*60
$SWITCH P16
$CASE 1
G00 X[P17-10] Y-90
G01 Z-0.5 F300
G01 X[P17+10] F1200
G01 Y-70
G01 X[P17-10]
G01 Y-90
$BREAK
$CASE 2
G00 X[P17+10] Y-80
G01 Z-0.5 F300
G02 X[P17-10] Y-80 I-10 J0 F1000
G02 X[P17+10] Y-80 I10 J0
$BREAK
$DEFAULT
G00 X[P17-10] Y-80
G01 Z-0.5 F300
G01 X[P17+10] F1200
G00 Z1
G00 XP17 Y-90
G01 Z-0.5 F300
G01 Y-70 F1200
$ENDSWITCH
G00 Z5
$ENDFOR
;
; 5) OPTIONAL DEEP CHAMFER PASS, DISABLED: N80 and N90 are jumped over
N70 $GOTO N100
N80 G00 X0 Y0
N90 G01 Z-3 F100
N100: G00 Z10
;
; 6) DOTS ON Y80 EVERY 20 MM FROM X-80; STOP BEFORE A DOT LIES MORE THAN
;    120 MM FROM PART ZERO (X100 WOULD BE 128.06 MM AWAY)
P20 = -80
P23 = 0 ; dot counter
$WHILE P20 <= 120
P21 = SQRT[P20*P20 + 80*80]
$IF P21 > 120
P0 = 1
$ENDIF
$IF P0==1 $GOTO [DONE]
V.P.ANGLE = ARG[P20, 80] ; polar angle of the dot: 45 to 135 degrees
P24 = 0.3 + ABS[P20]/200
$IF [P23 MOD 2] == 1
P24 = P24 + 0.2
$ENDIF
G00 XP20 Y80
G01 Z[-P24] F200
G00 Z2
P23 += 1
P20 = P20 + 20
$ENDWHILE
[DONE]
G00 Z20
M05
M30
