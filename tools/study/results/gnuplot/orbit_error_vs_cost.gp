set terminal pngcairo size 960,600 noenhanced font 'sans,10'
set output 'orbit_error_vs_cost.png'
set title 'orbit: worst energy error over 60 s vs cost (dt 1/30 .. 1/1000)'
set xlabel 'ms of World::step per simulated second'
set ylabel 'max |dE / E0| over 60 s'
set grid
set key outside right top
set logscale x
set format x '%g'
set logscale y
set format y '%.0e'
$d0 << EOD
0.0238411 0.889424038
0.0475802 0.756518967
0.0954749 0.699543274
0.190982 0.576513271
0.382808 0.401003258
0.805331 0.274558846
EOD
$d1 << EOD
0.022564 0.0738404567
0.0448332 0.0328915623
0.0896802 0.0154979373
0.179481 0.00752092136
0.357668 0.00371211759
0.745474 0.00178506175
EOD
$d2 << EOD
0.0225498 0.0659546554
0.0450577 0.0310181289
0.0899207 0.0150574855
0.250384 0.007410636
0.373011 0.00369506438
0.756681 0.00179798568
EOD
$d3 << EOD
0.0246704 4.60343394e-05
0.0495134 6.84261517e-06
0.0990875 6.23083517e-06
0.197921 2.02511157e-05
0.395952 2.55956594e-05
0.839485 3.82991964e-05
EOD
$d4 << EOD
0.0240152 0.88942511
0.0480501 0.756519419
0.0959412 0.699541644
0.191923 0.576513422
0.383504 0.401004155
0.799465 0.274559008
EOD
$d5 << EOD
0.0226499 0.0738385522
0.0452843 0.0328850647
0.0900172 0.0154968794
0.180361 0.00751983705
0.36131 0.00370373909
0.754021 0.0017638949
EOD
$d6 << EOD
0.0228318 0.0659521869
0.0455771 0.031020147
0.0910694 0.0150445135
0.181483 0.007408458
0.364738 0.00367610856
0.768564 0.00175755463
EOD
$d7 << EOD
0.0241297 4.84348735e-05
0.0481171 1.62716762e-06
0.0960958 5.77895853e-08
0.192693 2.23895106e-09
0.386183 9.70615106e-11
0.809125 3.96495994e-12
EOD
plot $d0 using 1:2 with linespoints title "ExplicitEuler float", \
     $d1 using 1:2 with linespoints title "SemiImplicitEuler float", \
     $d2 using 1:2 with linespoints title "ExactBallistic float", \
     $d3 using 1:2 with linespoints title "Rk4 float", \
     $d4 using 1:2 with linespoints dashtype 2 title "ExplicitEuler double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SemiImplicitEuler double", \
     $d6 using 1:2 with linespoints dashtype 2 title "ExactBallistic double", \
     $d7 using 1:2 with linespoints dashtype 2 title "Rk4 double"
