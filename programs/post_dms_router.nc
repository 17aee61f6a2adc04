DMS_ROUTER1
N10 ; A program in the form the Autodesk "DMS Router with FAGOR 8065" post writes it
N20 ; (the program name alone on the first line, N-numbered blocks; see README "CAM posts").
N30 ; It passes "fagorcnc check" with warnings only; "--strict" refuses the name line and G501/G500.
N40 ; T1 D=12 - ZMIN=-6 - FLAT END MILL
N50 #MCS OFF
N60 #HSC OFF
N70 G71 G80 G90
N80 G0 G53 Z0
N90 T1 M6
N100 S18000 M3
N110 G4 K3
N120 G54
N130 ;(ORGX58=0,ORGY58=0,ORGZ58=0)
N140 G58
N150 G159 =5
N160 G501 A100 E0.001 M2
N170 G0 X-20 Y-20
N180 G0 Z10
N190 G1 Z-6 F1200
N200 G1 G41 X0 Y0 D1 F3000
N210 G1 X80
N220 G1 Y40
N230 G1 X0
N240 G1 Y0
N250 G1 G40 X-20 Y-20
N260 G0 Z10
N270 G500
N280 G0 #MCS Z0
N290 M5
N300 M30
