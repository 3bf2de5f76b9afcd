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
0.0238453 0.889424038
0.0483038 0.756518967
0.12453 0.699543274
0.249094 0.576513271
0.49862 0.401003258
1.02722 0.274558846
EOD
$d1 << EOD
0.0291872 0.0738404567
0.0594701 0.0328915623
0.0902508 0.0154979373
0.178838 0.00752092136
0.366383 0.00371211759
0.745929 0.00178506175
EOD
$d2 << EOD
0.0227205 0.0659546554
0.0452199 0.0310181289
0.0906498 0.0150574855
0.180479 0.007410636
0.361673 0.00369506438
0.753386 0.00179798568
EOD
$d3 << EOD
0.0244623 4.60343394e-05
0.0489957 6.84261517e-06
0.099626 6.23083517e-06
0.198652 2.02511157e-05
0.394174 2.55956594e-05
0.81833 3.82991964e-05
EOD
$d4 << EOD
0.0245206 0.88942511
0.0491868 0.756519419
0.0984672 0.699541644
0.197245 0.576513422
0.392165 0.401004155
0.818058 0.274559008
EOD
$d5 << EOD
0.0231965 0.0738385522
0.0463265 0.0328850647
0.093544 0.0154968794
0.184544 0.00751983705
0.371656 0.00370373909
0.769246 0.0017638949
EOD
$d6 << EOD
0.0232567 0.0659521869
0.0464542 0.031020147
0.0930509 0.0150445135
0.186287 0.007408458
0.375375 0.00367610856
0.778138 0.00175755463
EOD
$d7 << EOD
0.0248348 4.84348735e-05
0.0497504 1.62716762e-06
0.0997304 5.77895853e-08
0.204173 2.23895106e-09
0.410011 9.70615106e-11
0.852002 3.96495994e-12
EOD
plot $d0 using 1:2 with linespoints title "ExplicitEuler float", \
     $d1 using 1:2 with linespoints title "SemiImplicitEuler float", \
     $d2 using 1:2 with linespoints title "ExactBallistic float", \
     $d3 using 1:2 with linespoints title "Rk4 float", \
     $d4 using 1:2 with linespoints dashtype 2 title "ExplicitEuler double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SemiImplicitEuler double", \
     $d6 using 1:2 with linespoints dashtype 2 title "ExactBallistic double", \
     $d7 using 1:2 with linespoints dashtype 2 title "Rk4 double"
