%L SAFEZ
; retract to the clearance plane Z5
G00 Z5
M17
%L SPOT
; modal subroutine: spot at the current XY position, back to Z2
; P0 (letter A) = spot depth below Z0
G01 Z[-P0] F150
G00 Z2
#RET
%L CIRCLE
; circular groove, counter-clockwise, two half circles
; P0 (A) = centre X, P1 (B) = centre Y, P5 (F) = radius,
; P2 (C) = depth below Z0, 1 mm when the call does not pass it
$IF EXIST[P2] == FALSE
P2 = 1
$ENDIF
G00 X[P0+P5] YP1
G01 Z-[P2] F200
G03 X[P0-P5] YP1 I-[P5] J0 F800
G03 X[P0+P5] YP1 IP5 J0
LL SAFEZ
M17
%L SLOT
; straight slot from (P10,P11) to (P12,P11), P13 deep.
; Called with LL: it works on the caller's local parameters.
G00 XP10 YP11
G01 Z[-P13] F200
G01 XP12 F900
LL SAFEZ
M17
%L FACE
; facing at Z0 over X-55..55, Y-30..30, zigzag with a 20 mm step.
; Called with #CALL: P0 here is a new local parameter, not the caller's P0.
G00 X-55 Y-40
G00 Z2
G01 Z0 F500
$FOR P0 = 0, 3, 1
G01 Y[-30+P0*20] F1500
$IF [P0 MOD 2] == 0
G01 X55
$ELSE
G01 X-55
$ENDIF
$ENDFOR
LL SAFEZ
#RET
%SUBDEMO
; SUBROUTINE DEMO: faces the top of the stock (#CALL), mills two circular
; grooves (#PCALL), a slot (LL) and spots four holes with a modal
; subroutine (#MCALL ... #MDOFF). Stock top at Z0.5, part zero G54.
G71 G90 G17 G54
T4 D1 M06
S2500 M03
G00 Z20
P0 = 7 ; the main program's own P0
#CALL FACE
; letters A..Z stand for P0..P25: A10 -> P0=10, B2.5 -> P1=2.5, F6 -> P5=6
#PCALL CIRCLE A10 B2.5 P5=3
#PCALL CIRCLE A-25 B-10 C2 F6
; back here P0 is still 7: FACE and CIRCLE had their own parameter level
P10=-40 P11=-25 P12=40 P13=1.5
LL SLOT
; spot four holes on Y25, 1 mm deep (A1 -> P0=1 inside SPOT).
; SPOT is modal: it runs at the #MCALL and again after every move until #MDOFF.
G00 X-45 Y25
G00 Z2
#MCALL SPOT A1
G00 X-15
G00 X15
G00 X45
#MDOFF
G00 Z50
M05
M30
