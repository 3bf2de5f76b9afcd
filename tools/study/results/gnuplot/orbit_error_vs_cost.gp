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
0.0184425 0.889424038
0.0367264 0.756518967
0.0744565 0.699543274
0.148358 0.576513271
0.297387 0.401003258
0.603518 0.274558846
EOD
$d1 << EOD
0.0166678 0.0738404567
0.0334253 0.0328915623
0.0685488 0.0154979373
0.142306 0.00752092136
0.27459 0.00371211759
0.569787 0.00178506175
EOD
$d2 << EOD
0.0171885 0.0659546554
0.0344016 0.0310181289
0.069685 0.0150574855
0.13843 0.007410636
0.278661 0.00369506438
0.57219 0.00179798568
EOD
$d3 << EOD
0.0185042 4.60343394e-05
0.0370734 6.84261517e-06
0.073858 6.23083517e-06
0.14828 2.02511157e-05
0.295659 2.55956594e-05
0.618461 3.82991964e-05
EOD
$d4 << EOD
0.0185649 0.88942511
0.0373394 0.756519419
0.0745101 0.699541644
0.148727 0.576513422
0.298743 0.401004155
0.622049 0.274559008
EOD
$d5 << EOD
0.0173701 0.0738385522
0.0349551 0.0328850647
0.0701707 0.0154968794
0.139706 0.00751983705
0.277247 0.00370373909
0.583124 0.0017638949
EOD
$d6 << EOD
0.0178555 0.0659521869
0.0361186 0.031020147
0.071633 0.0150445135
0.141553 0.007408458
0.288053 0.00367610856
0.595115 0.00175755463
EOD
$d7 << EOD
0.0189253 4.84348735e-05
0.0382561 1.62716762e-06
0.0763721 5.77895853e-08
0.149546 2.23895106e-09
0.305872 9.70615106e-11
0.641717 3.96495994e-12
EOD
plot $d0 using 1:2 with linespoints title "ExplicitEuler float", \
     $d1 using 1:2 with linespoints title "SemiImplicitEuler float", \
     $d2 using 1:2 with linespoints title "ExactBallistic float", \
     $d3 using 1:2 with linespoints title "Rk4 float", \
     $d4 using 1:2 with linespoints dashtype 2 title "ExplicitEuler double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SemiImplicitEuler double", \
     $d6 using 1:2 with linespoints dashtype 2 title "ExactBallistic double", \
     $d7 using 1:2 with linespoints dashtype 2 title "Rk4 double"
