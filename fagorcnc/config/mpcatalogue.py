"""The manual's catalogue of machine-parameter variables (seed 002 §22.4-§22.12, L17975-L29306; spec 07 part B).

One line per variable: its family, name, number of bracket indices, the kinds of axis it is valid for,
its access and timing, where fagorcnc takes its value from, and the seed line that defines it.

Families: ``MPG`` general (system), ``MPGCH`` general of the channel (``V.[ch].MPG.``), ``MPA`` axis or
spindle, ``MPASET`` axis or spindle per parameter set (``[set]`` first), ``MPMAN``, ``MPM``, ``MPK``,
``TM`` (magazine parameters), ``MTB``, ``DRV``.  In a name, ``#`` stands for a number built into it
(``MPG.CHAXISNAME2``) and ``?`` for an optional one (``MPMAN.JOGKEYDEF`` is keyboard 1, ``JOGKEY2DEF``
keyboard 2).

Kinds (``on``): ``l`` linear axis, ``r`` rotary axis, ``s`` spindle; ``-`` for no axis selector.
Access: ``RP`` read, preparation value; ``RE`` read, execution value (the read stops block preparation,
L17437); ``IF`` read only by the interface, never by a part program; ``RWE`` read and written by the
program at execution (``MTB.P``).  Every machine parameter is read-only from a program (L17422,
§1.9 L1809-L1812) except ``MTB.P``/``PF`` and ``DRV`` variables.

Sources (``src``):

* ``=v``: the value the manual gives for what fagorcnc's machine does not have or always does
  (no tandem pair: 0, L18009; the simulator's drive type 16, L21159; ...);
* a word: a field of fagorcnc's own machine file (``axes.X.max_velocity`` for ``G00FEED``...),
  the mapping is :data:`fagorcnc.interp.mpvars` ``SOURCES``;
* ``free``: a parameter fagorcnc does not use (drives, PLC, hand wheels, jog, servo gains): its value
  comes from the machine file's ``[machine_parameters]`` table, in the manual's spelling
  (``"MPA.FFGAIN.X" = 100``); when the file does not give it a program reading it is refused (INT245);
* ``none``: a parameter that would change what fagorcnc computes and that fagorcnc does not model:
  always refused (INT240), never given a value the interpreter would not honour.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

#: family  name  indices  on  access  source  seed-line
_TABLE = """
MPG NCHANNEL 0 - RP =1 L17979
MPG NAXIS 0 - RP naxis L17987
MPG AXISNAME# 0 - IF - L17993
MPG NSPDL 0 - RP nspdl L18304
MPG SPDLNAME# 0 - IF - L18310
MPG TMASTERAXIS 1 - RP =0 L18009
MPG TSLAVEAXIS 1 - RP =0 L18021
MPG TORQDIST 1 - RP =0 L18040
MPG PRELOAD 1 - RE =0 L18060
MPG PRELFITI 1 - RE =0 L18083
MPG TPROGAIN 1 - RE =0 L18104
MPG TINTIME 1 - RE =0 L18124
MPG TCOMPLIM 1 - RE =0 L18139
MPG MASTERAXIS 1 - RP =0 L18157
MPG SLAVEAXIS 1 - RP =0 L18174
MPG WARNCOUPE 1 - RP =0 L18186
MPG MAXCOUPE 1 - RP =0 L18200
MPG DIFFCOMP 1 - RP =0 L18213
MPG MAXDIFF 1 - RP =0 L18236
MPG MULNGROUP 0 - RP =0 L18249
MPG MULNAXIS 1 - RP nogroup L18255
MPG MULAXISNAME# 1 - RP nogroup L18265
MPG LOOPTIME 0 - RP looptime L18328
MPG PRGFREQ 0 - RP free L18334
MPG SERBRATE 0 - RP free L18364
MPG SERPOWSE 0 - RP free L18374
MPG MLINK 0 - RP free L18382
MPG DATASIZE 0 - RP free L18392
MPG CANMODE 0 - RP free L18430
MPG CANLENGTH 0 - RP free L18440
MPG RSTYPE 0 - RP free L18452
MPG INCHES 0 - RP inches L18497
MPG MAXLOCP 0 - RP maxlocp L18509
MPG MINLOCP 0 - RP minlocp L18515
MPG MAXGLBP 0 - RP maxglbp L18521
MPG MINGLBP 0 - RP minglbp L18527
MPG ROPARMIN 0 - RP =0 L18556
MPG ROPARMAX 0 - RP =0 L18564
MPG MAXCOMP 0 - RP maxcomp L18572
MPG MINCOMP 0 - RP mincomp L18578
MPG BKUPCUP 0 - RP free L18584
MPG MOVAXIS 1 - RP =0 L18592
MPG COMPAXIS 1 - RP =0 L18604
MPG NPCROSS 1 - RP =0 L18627
MPG TYPCROSS 1 - RP =0 L18637
MPG BIDIR 1 - RP =0 L18651
MPG REFNEED 1 - RP =0 L18690
MPG POSITION 2 - RP =0 L18705
MPG POSERROR 2 - RP =0 L18717
MPG NEGERROR 2 - RP =0 L18733
MPG VCOMPAXIS# 1 - RP =0 L18761
MPG VCOMPFILE 1 - RP =0 L18773
MPG MINAENDW 0 - RP free L18786
MPG REFTIME 0 - RP free L18792
MPG HTIME 0 - RP free L18798
MPG DTIME 0 - RP free L18804
MPG TTIME 0 - RP free L18823
MPG NDIMOD 0 - RP free L18831
MPG NDOMOD 0 - RP free L18841
MPG DIMODADDR 1 - RP free L18851
MPG DOMODADDR 1 - RP free L18861
MPG NPT100 0 - RP free L18883
MPG PT100 1 - RP free L18889
MPG PROBE 0 - RP free L18901
MPG PROBETYPE# 0 - RP free L18911
MPG PRBDI# 0 - RP free L18950
MPG PRBPULSE# 0 - RP free L18972
MPG PLCDATASIZE 0 - RP free L19015
MPG NLOCOUT 0 - RP free L19023
MPG EXPSCHK 0 - RP free L19029
MPG SWTOUTPUT 0 - RP free L19041
MPG SWTDELAY 0 - RP free L19047
MPG PWMOUTPUT 0 - RP free L19074
MPG PWMCANCEL 0 - RP free L19084
MPG BKUPREG 0 - RP free L19096
MPG BKUPCOUN 0 - RP free L19102
MPG NKEYBD 0 - RP free L19165
MPG KEYBDCH 1 - RP free L19171
MPG TOOLOFSG 0 - RP =0 L19133
MPG SYNCCANCEL 0 - RP free L19149
MPG PLCTYPE 0 - RP free L19210
MPG NSERCOUNT 0 - RP free L19277
MPG SERCOUNTID 1 - RP free L19283
MPG RENAMECANCEL 0 - RP renamecancel L19222
MPG FINEORG 0 - RP =0 L19265
MPGCH GROUPID 0 - RP =0 L19308
MPGCH CHTYPE 0 - RP =0 L19320
MPGCH HIDDENCH 0 - RP =0 L19338
MPGCH CHNAXIS 0 - RP chnaxis L19375
MPGCH CHAXISNAME# 0 - IF - L19389
MPGCH GEOCONFIG 0 - RP geoconfig L19400
MPGCH CHNSPDL 0 - RP chnspdl L19444
MPGCH CHSPDLNAME# 0 - IF - L19458
MPGCH CAXNAME 0 - IF - L19471
MPGCH ALIGNC 0 - RP none L19509
MPGCH PREPFREQ 0 - RP free L19529
MPGCH ANTIME 0 - RP free L19539
MPGCH FEEDAVRG 0 - RP none L19551
MPGCH SMOOTHFREQ 0 - RP none L19658
MPGCH CORNER 0 - RP corner L19668
MPGCH HSCFILTFREQ 0 - RP none L19678
MPGCH FASTFACTOR 0 - RP fastfactor L19688
MPGCH FTIMELIM 0 - RP none L19698
MPGCH MINCORFEED 0 - RP mincorfeed L19723
MPGCH FSMOOTHFREQ 0 - RP none L19733
MPGCH FASTFILTFREQ 0 - RP none L19743
MPGCH FREQRES 0 - RP free L19753
MPGCH SOFTFREQ 0 - RP none L19763
MPGCH HSCROUND 0 - RP hscround L19784
MPGCH SURFFILFREQ 0 - RP none L19794
MPGCH HSCDEFAULMODE 0 - RP hscmode L19804
MPGCH VIRTAXISNAME 0 - RP none L19820
MPGCH VIRTAXCANCEL 0 - RP none L19855
MPGCH KINID 0 - RP kinid L19871
MPGCH CSCANCEL 0 - RP none L19889
MPGCH LINKCANCEL 0 - RP none L19935
MPGCH MIRRORCANCEL 0 - RP mirrorcancel L19953
MPGCH SLOPETYPE 0 - RE slopetype L19967
MPGCH IPLANE 0 - RP iplane L20013
MPGCH ISYSTEM 0 - RP isystem L20031
MPGCH IMOVE 0 - RP imove L20071
MPGCH IFEED 0 - RP ifeed L20089
MPGCH FPRMAN 0 - RP free L20107
MPGCH LCOMPTYP 0 - RP none L20142
MPGCH ICORNER 0 - RP icorner L20157
MPGCH IRCOMP 0 - RP ircomp L20175
MPGCH COMPCANCEL 0 - RP none L20218
MPGCH ROUNDTYPE 0 - RP roundtype L20236
MPGCH MAXROUND 0 - RP maxround L20276
MPGCH ROUNDFEED 0 - RP roundfeed L20286
MPGCH CIRINERR 0 - RP cirinerr L20298
MPGCH CIRINFACT 0 - RP cirinfact L20308
MPGCH MAXOVR 0 - RP =200 L20340
MPGCH RAPIDOVR 0 - RP =1 L20355
MPGCH FEEDND 0 - RP none L20376
MPGCH MINDYNOVR 0 - RP free L20408
MPGCH MAXDYNOVR 0 - RP free L20418
MPGCH STEPDYNOVR 0 - RP free L20428
MPGCH IMOVEMACH 0 - RP none L20440
MPGCH XFITOIND 0 - RP free L20469
MPGCH TOOLSUB 0 - IF - L20488
MPGCH REFPSUB 0 - IF - L20497
MPGCH OEMSUB# 0 - IF - L20506
MPGCH INT#SUB 0 - IF - L20545
MPGCH SUBPATH 0 - IF - L20556
MPGCH PRB1MIN 0 - RP free L20567
MPGCH PRB1MAX 0 - RP free L20577
MPGCH PRB2MIN 0 - RP free L20676
MPGCH PRB2MAX 0 - RP free L20686
MPGCH PRB3MIN 0 - RP free L20696
MPGCH PRB3MAX 0 - RP free L20706
MPGCH FUNPLC 0 - RP free L20718
MPGCH SUBINTSTOP 0 - RP free L20745
MPGCH MAXFEED 0 - RP maxfeed L20762
MPGCH DEFAULTFEED 0 - RP defaultfeed L20776
MPGCH RAPIDEN 0 - RP =0 L20811
MPGCH FRAPIDEN 0 - RP =0 L20826
MPGCH MAXACCEL 0 - RP maxaccel L20873
MPGCH MAXJERK 0 - RP maxjerk L20883
MPGCH RETRACAC 0 - RP free L20895
MPGCH NRETBLK 0 - RP free L20909
MPGCH RETMFUNC 0 - RP free L20932
MPGCH MASTERSPDL 0 - RP free L20964
MPA AXISEXCH 0 lrs RP axisexch L21089
MPA AXISTYPE 0 lr RE axistype L21117
MPA DRIVETYPE 0 lrs RE =16 L21159
MPA POSUNITS 0 lrs RP free L21182
MPA DRIVEID 0 lrs RE free L21243
MPA OPMODEP 0 lrs RE free L21300
MPA FBACKSRC 0 lrs RP free L21323
MPA FBACKDIFF 0 lrs RP free L21386
MPA FBMIXTIME 0 lrs RP free L21404
MPA MODCOMP 0 lrs RE free L21676
MPA HIRTH 0 lr RP =0 L21463
MPA HPITCH 0 lr RP =0 L21484
MPA FACEAXIS 0 l RP none L21500
MPA LONGAXIS 0 l RP none L21535
MPA AXISMODE 0 r RE axismode L21555
MPA UNIDIR 0 r RE unidir L21606
MPA SHORTESTWAY 0 r RE shortestway L21625
MPA CAXIS 0 rs RP caxis L21701
MPA CAXSET 0 rs RP free L21754
MPA PERCAX 0 rs RP none L21772
MPA M19SPDLEREV 0 s RP free L22009
MPA AUTOGEAR 0 s RP free L21839
MPA LOSPDLIM 0 s RP free L21858
MPA UPSPDLIM 0 s RP free L21913
MPA SPDLTIME 0 s RP free L21933
MPA SPDLSTOP 0 s RP spdlstop L21948
MPA SREVM05 0 s RP srevm05 L21990
MPA PLCOINC 0 lrs RP free L22453
MPA STEPOVR 0 s RP free L22064
MPA MINOVR 0 s RP free L22084
MPA MAXOVR 0 s RP free L22139
MPA SYNCSET 0 rs RP free L22161
MPA DSYNCVELW 0 lrs RP free L22216
MPA DSYNCPOSW 0 lrs RP free L22234
MPA TENDENCY 0 lrs RE free L22387
MPA TENDTIME 0 lrs RE free L22433
MPA POSLIMIT 0 lr RE poslimit L22291
MPA NEGLIMIT 0 lr RE neglimit L22306
MPA SWLIMITTOL 0 lr RE free L22321
MPA THREADOVR 0 s RP threadovr L22355
MPA OVRFILTER 0 s RP free L22370
MPA DWELL 0 lrs RP free L22510
MPA DIAMPROG 0 l RP diamprog L22530
MPA DECINPUT 0 lrs RE free L22698
MPA REFDIREC 0 lrs RE free L22675
MPA REFINI 0 s RP free L22748
MPA PROBEAXIS 0 lr RP free L22765
MPA PROBERANGE 0 lr RP free L22822
MPA PROBEFEED 0 lr RP free L22836
MPA PROBEDELAY 0 lr RP free L22850
MPA PROBEDELAY2 0 lr RP free L22887
MPA REPOSFEED 0 lr RE free L22903
MPA POSFEED 0 lrs RP free L22920
MPA FLIMIT 0 lr RP none L22962
MPA SLIMIT 0 s RP none L22976
MPA JOGFEED 0 lr RE free L22993
MPA JOGRAPFEED 0 lr RE free L23031
MPA MAXMANFEED 0 lr RE free L23046
MPA MAXMANACC 0 lr RP free L23061
MPA INCJOGDIST 1 lr RP free L23100
MPA INCJOGFEED 1 lr RP free L23118
MPA MPGRESOL 1 lr RP free L23138
MPA MPGFILTER ? lr RP free L23168
MPA MANPOSSW 0 lr RP free L23186
MPA MANNEGSW 0 lr RP free L23200
MPA MANFEEDP 0 lr RP free L23237
MPA IPOFEEDP 0 lr RP free L23251
MPA MANACCP 0 lr RP free L23265
MPA IPOACCP 0 lr RP free L23279
MPA LSCRWCOMP 0 lrs RP free L23312
MPA NPOINTS 0 lrs RP free L23334
MPA TYPLSCRW 0 lrs RP free L23388
MPA BIDIR 0 lrs RP free L23409
MPA REFNEED 0 lrs RP free L23470
MPA POSITION 1 lrs RP free L23492
MPA POSERROR 1 lrs RP free L23545
MPA NEGERROR 1 lrs RP free L23565
MPA ORDER 1 lrs RP free L23628
MPA TYPE 1 lrs RP free L23648
MPA FREQUENCY 1 lrs RP free L23709
MPA NORBWIDTH 1 lrs RP free L23729
MPA SHARE 1 lrs RP free L23789
MPA NPARSETS 0 lrs RP nparsets L23810
MPA DEFAULTSET 0 lrs RP defaultset L23860
MPASET PITCH 0 lrs RE free L23896
MPASET INPUTREV 0 lrs RE free L23925
MPASET OUTPUTREV 0 lrs RE free L23972
MPASET NPULSES 0 lrs RE free L23992
MPASET PITCH2 0 lrs RE free L24055
MPASET INPUTREV2 0 lrs RE free L24083
MPASET OUTPUTREV2 0 lrs RE free L24217
MPASET NPULSES2 0 lrs RE free L24238
MPASET SINMAGNI 0 lrs RE free L24376
MPASET ABSFEEDBACK 0 lrs RE free L24399
MPASET FBACKAL 0 lrs RE free L24455
MPASET LOOPCH 0 lrs RE free L24482
MPASET AXISCH 0 lrs RE free L24534
MPASET BACKLASH 0 lrs RE free L24626
MPASET BAKANOUT 0 lrs RE free L24683
MPASET BAKTIME 0 lrs RE free L24711
MPASET ACTBAKAN 0 lrs RP free L24764
MPASET PEAKDISP 0 lrs RP free L24787
MPASET REVEHYST 0 lrs RP free L24845
MPASET INPOSW 0 lrs RE free L24603
MPASET MAXVOLT 0 lrs RE free L24944
MPASET MAXFREQ 0 s RE free L24996
MPASET MAXRPM 0 lrs RE free L25015
MPASET G00FEED 0 lrs RE g00feed L24868
MPASET MAXFEED 0 lrs RP axismaxfeed L24921
MPASET FRAPIDEN 0 lrs RP =0 L25037
MPASET PROGAIN 0 lrs RE free L25098
MPASET FFWTYPE 0 lrs RE free L25233
MPASET FFGAIN 0 lrs RE free L25258
MPASET MANFFGAIN 0 lrs RE free L25331
MPASET ACFWFACTOR 0 lrs RE free L25392
MPASET ACFGAIN 0 lrs RE free L25412
MPASET MANACFGAIN 0 lrs RE free L25473
MPASET LACC1 0 lrs RE accel L25503
MPASET LACC2 0 lrs RE accel L25550
MPASET LFEED 0 lrs RE none L25570
MPASET ACCEL 0 lrs RE accel L25630
MPASET DECEL 0 lrs RE accel L25651
MPASET ACCJERK 0 lrs RE jerk L25704
MPASET DECJERK 0 lrs RE jerk L25724
MPASET G0ACDCJERK 0 lrs RE =0 L25779
MPASET LACC1G0 0 lrs RE accel L25805
MPASET LACC2G0 0 lrs RE accel L25854
MPASET LFEEDG0 0 lrs RE none L25874
MPASET ACCELG0 0 lrs RE accel L25939
MPASET DECELG0 0 lrs RE accel L25960
MPASET ACCJERKG0 0 lrs RE jerk L26013
MPASET DECJERKG0 0 lrs RE jerk L26033
MPASET CORNERACC 0 lrs RP none L26169
MPASET CURVACC 0 lrs RP none L26189
MPASET CORNERJERK 0 lrs RP none L26241
MPASET CURVJERK 0 lrs RP none L26260
MPASET FASTACC 0 lrs RP none L26280
MPASET MAXERROR 0 lrs RP none L26331
MPASET CONTERROR 0 lrs RP none L26352
MPASET REFVALUE 0 lrs RE refvalue L26430
MPASET REFSHIFT 0 lrs RE free L26490
MPASET REFFEED1 0 lrs RE free L26511
MPASET REFFEED2 0 lrs RE free L26563
MPASET POSINREF 0 lrs RP none L26649
MPASET REFPULSE 0 lrs RP free L26584
MPASET ABSOFF 0 lrs RP free L26669
MPASET EXTMULT 0 lrs RP free L26723
MPASET I0CODDI1 0 lrs RP free L26742
MPASET I0CODDI2 0 lrs RP free L26800
MPASET I0TYPE 0 lrs RE free L26405
MPASET FLWEMONITOR 0 lrs RP free L26821
MPASET MINFLWE 0 lrs RE free L26880
MPASET MAXFLWE 0 lrs RE free L26901
MPASET FEDYNFAC 0 lrs RE free L26958
MPASET ESTDELAY 0 lrs RE free L26978
MPASET INPOMAX 0 lrs RE free L27039
MPASET INPOTIME 0 lrs RE free L27059
MPASET DISTLUBRI 0 lrs RE free L27113
MPASET MODUPLIM 0 r RE moduplim L27136
MPASET MODLOWLIM 0 r RE modlowlim L27189
MPASET MODNROT 0 r RE free L27209
MPASET MODERR 0 r RE free L27262
MPASET SZERO 0 s RP free L27284
MPASET POLARM3 0 s RP free L27301
MPASET POLARM4 0 s RP free L27349
MPASET SERVOOFF 0 lrs RE free L27407
MPASET MINANOUT 0 lrs RE free L27431
MPASET ANAOUTTYPE 0 lrs RP free L27489
MPASET ANAOUTID 0 lrs RP free L27513
MPASET COUNTERTYPE 0 lrs RP free L27569
MPASET COUNTERID 0 lrs RP free L27644
MPASET DRIVESET 0 lrs RP free L27670
MPASET FEEDBACKTYPE 0 lrs RP free L27719
MPASET SSITYPE 0 lrs RP free L27739
MPASET SSICLKFREQ 0 lrs RP free L27800
MPASET SSIDATALENGTH 0 lrs RP free L27820
MPASET SSIPACKFORMAT 0 lrs RP free L27889
MPASET SSICRCTYPE 0 lrs RP free L27967
MPASET SSICRCBITS 0 lrs RP free L27990
MPASET SSISTARTBITS 0 lrs RP free L28051
MPASET SSIALARMBITS 0 lrs RP free L28070
MPASET SSIALARMLEVEL 0 lrs RP free L28090
MPASET SSIDATAMODE 0 lrs RP free L28141
MPASET STARTDELAY 0 lrs RP free L28165
MPASET SSIRESOL 0 lrs RP free L28223
MPASET AXDELAY 0 lrs RP free L28245
MPMAN NMPG 0 - RP =0 L28329
MPMAN COUNTERTYPE 1 - RP nompg L28335
MPMAN COUNTERID 1 - RP nompg L28349
MPMAN MPGAXIS 1 - RP nompg L28392
MPMAN JOGKEY?DEF 1 - RP free L28412
MPMAN JOGTYPE 0 - RP free L28556
MPMAN USERKEY?DEF 1 - RP free L28569
MPMAN HBLS 0 - RP free L28618
MPM MTABLESIZE 0 - RP mtablesize L28673
MPM MNUM 1 - RP mnum L28679
MPM SYNCHTYPE 1 - RP synchtype L28692
MPM MPROGNAME 1 - IF - L28711
MPM MTIME 1 - RP none L28734
MPM MPLC 1 - RP none L28745
MPK PARAM_D_SIZE 1 - RP none L28882
MPK PARAM_I_SIZE 1 - RP none L28892
MPK AUXCTE_SIZE 1 - RP none L28917
MPK KINDATA_SIZE 1 - RP none L28927
TM NTOOLMZ 0 - RP =0 L29011
TM MZGROUND 0 - RP =1 L29017
TM MZSIZE 1 - RP nomz L29027
TM MZRANDOM 1 - RP nomz L29037
TM MZTYPE 1 - RP nomz L29073
TM MZCYCLIC 1 - RP nomz L29087
TM MZOPTIMIZED 1 - RP nomz L29106
TM MZRESPECTSIZE 1 - RP nomz L29147
TM MZM6ALONE 1 - RP nomz L29157
MTB SIZE 0 - RE mtbsize L29192
MTB P 1 - RWE mtb L29198
MTB PF 1 - RWE mtb L29219
DRV SIZE 0 - RE =0 L29268
"""

#: sources that are fields of an axis of fagorcnc's machine file: for a spindle they come from
#: ``[machine_parameters]`` (``"MPA.G00FEED.S" = 3000``)
AXIS_FIELDS = frozenset({"g00feed", "axismaxfeed", "accel", "jerk", "refvalue", "axisexch"})

#: sources fagorcnc uses that the machine file gives in ``[machine_parameters]`` when it differs from the
#: value fagorcnc takes without it (interp/spindle_config.py: RENAMECANCEL 0; THREADOVR 0, interp/threading.py)
GIVEN = frozenset({"renamecancel", "threadovr"})

#: prefix of a family in a variable's name
PREFIX = {"MPG": "MPG", "MPGCH": "MPG", "MPA": "MPA", "MPASET": "MPA", "MPMAN": "MPMAN", "MPM": "MPM",
          "MPK": "MPK", "TM": "TM", "MTB": "MTB", "DRV": "DRV"}


@dataclass(frozen=True)
class Entry:
    """One machine-parameter variable of the manual's catalogue."""

    family: str
    name: str                 # the manual's name, ``#``/``?`` for a built-in number
    indices: int              # bracket indices after the name ([set] of MPASET not counted); -1: optional one
    on: str                   # "l", "r", "s" kinds the axis selector may name; "" for none
    access: str               # "RP", "RE", "IF", "RWE"
    source: str               # "=v", a field name, "free", "none", "-"
    seed: str

    @property
    def execution(self) -> bool:
        """The read gives the execution value: it stops block preparation (L17437)."""
        return self.access in ("RE", "RWE")

    @property
    def per_set(self) -> bool:
        return self.family == "MPASET"


def _parse() -> tuple[dict[tuple[str, str], Entry], list[tuple[str, re.Pattern, Entry]]]:
    exact: dict[tuple[str, str], Entry] = {}
    numbered: list[tuple[str, re.Pattern, Entry]] = []
    for line in _TABLE.strip().splitlines():
        family, name, idx, on, access, source, seed = line.split()
        entry = Entry(family, name, -1 if idx == "?" else int(idx), "" if on == "-" else on, access, source, seed)
        prefix = PREFIX[family]
        if "#" in name or "?" in name:
            pattern = re.escape(name).replace("\\#", "#").replace("\\?", "?")
            pattern = pattern.replace("#", r"(\d+)").replace("?", r"(\d*)")
            numbered.append((prefix, re.compile(pattern), entry))
        else:
            exact.setdefault((prefix, name), entry)
            if family in ("MPA", "MPASET"):   # every MPA variable of a spindle is also an SP one (L17574)
                exact.setdefault(("SP", name), entry)
    return exact, numbered


_EXACT, _NUMBERED = _parse()


def lookup(prefix: str, name: str) -> tuple[Entry, int | None] | None:
    """The catalogue entry of ``prefix.name`` and the number built into the name (None without one);
    ``MPG`` names of the system and of the channel share the prefix (L17975, L19304)."""
    entry = _EXACT.get((prefix, name))
    if entry is not None:
        return entry, None
    for p, pattern, entry in _NUMBERED:
        if p == prefix:
            m = pattern.fullmatch(name)
            if m:
                return entry, int(m.group(1)) if m.group(1) else None
    return None


def entries() -> list[Entry]:
    """Every entry of the catalogue, in the manual's order."""
    seen: dict[int, Entry] = {}
    for e in list(_EXACT.values()) + [e for _p, _r, e in _NUMBERED]:
        seen.setdefault(id(e), e)
    return sorted(seen.values(), key=lambda e: int(e.seed[1:]))


#: ``[machine_parameters]`` key: PREFIX.NAME[i][j].AXIS (the axis or spindle name for MPA)
_KEY = re.compile(r"(MPG|MPA|MPMAN)\.([A-Z][A-Z0-9_]*)((?:\[\d+\])*)(?:\.([A-Z][0-9]?))?")


def parse_key(key: str) -> tuple[Entry, tuple[int, ...], str | None] | str:
    """A ``[machine_parameters]`` key as (entry, indices, axis), or the reason it is refused.

    A per-set parameter may leave its ``[set]`` out (fagorcnc's machine has one set, NPARSETS = 1).  A
    parameter fagorcnc computes for an axis (``G00FEED``) may be given for a spindle, which fagorcnc's
    machine file otherwise describes by its name only."""
    m = _KEY.fullmatch(key)
    if m is None:
        return "expected the manual's name of a machine parameter, e.g. \"MPA.FFGAIN.X\" or \"MPG.PRB1MIN\""
    prefix, name, brackets, axis = m.groups()
    found = lookup(prefix, name)
    if found is None:
        return f"{prefix}.{name} is not a machine parameter of the manual's catalogue (seed 002 ch. 22.4-22.12)"
    entry, number = found
    spindle_value = axis is not None and axis[0] == "S" and "s" in entry.on and entry.source in AXIS_FIELDS
    if entry.source != "free" and entry.source not in GIVEN and not spindle_value:
        why = ("fagorcnc computes it from the rest of the machine file" if entry.source not in ("none", "-")
               else "fagorcnc does not model it" if entry.source == "none" else "a part program cannot read it")
        return f"{prefix}.{name} cannot be given here: {why}"
    idx = tuple(int(x) for x in re.findall(r"\d+", brackets))
    if entry.per_set and idx[:1] == (1,) and len(idx) == max(entry.indices, 0) + 1:
        idx = idx[1:]
    wanted = entry.indices
    if not (len(idx) == wanted or (wanted == -1 and len(idx) <= 1)):
        return f"{prefix}.{name} takes {max(wanted, 0)} index(es) in brackets" + (" (its [set] may be left out)"
                                                                                  if entry.per_set else "")
    if bool(entry.on) != (axis is not None):
        return f"{prefix}.{name} " + ("needs the axis or spindle: .X, .S" if entry.on else "takes no axis")
    if "#" in entry.name or "?" in entry.name:
        idx = (number if number is not None else 1, *idx)
    return entry, idx, axis
