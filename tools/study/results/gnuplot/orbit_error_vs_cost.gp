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
0.0231528 0.889424038
0.046594 0.756518967
0.10045 0.699543274
0.185079 0.576513271
0.436874 0.401003258
0.78359 0.274558846
EOD
$d1 << EOD
0.0211081 0.0738404567
0.042429 0.0328915623
0.0893292 0.0154979373
0.171094 0.00752092136
0.34081 0.00371211759
0.710109 0.00178506175
EOD
$d2 << EOD
0.0212873 0.783408519
0.0427105 0.707640538
0.0851099 0.579615431
0.170917 0.401151805
0.340786 0.283759068
0.707632 0.167035774
EOD
$d3 << EOD
0.0227359 4.60343394e-05
0.045794 6.84261517e-06
0.0916892 6.23083517e-06
0.184304 2.02511157e-05
0.366867 2.55956594e-05
0.766303 3.82991964e-05
EOD
$d4 << EOD
0.0222012 0.88942511
0.0443595 0.756519419
0.0889991 0.699541644
0.178566 0.576513422
0.356918 0.401004155
0.741571 0.274559008
EOD
$d5 << EOD
0.0207091 0.0738385522
0.0415997 0.0328850647
0.0829941 0.0154968794
0.166053 0.00751983705
0.330721 0.00370373909
0.701032 0.0017638949
EOD
$d6 << EOD
0.0206628 0.783410124
0.0419298 0.707640012
0.0833516 0.579615926
0.172573 0.401162695
0.339157 0.283755444
0.708557 0.167029893
EOD
$d7 << EOD
0.0222774 4.84348735e-05
0.0450164 1.62716762e-06
0.0897623 5.77895853e-08
0.179455 2.23895106e-09
0.361355 9.70615106e-11
0.755282 3.96495994e-12
EOD
plot $d0 using 1:2 with linespoints title "ExplicitEuler float", \
     $d1 using 1:2 with linespoints title "SemiImplicitEuler float", \
     $d2 using 1:2 with linespoints title "ExactBallistic float", \
     $d3 using 1:2 with linespoints title "Rk4 float", \
     $d4 using 1:2 with linespoints dashtype 2 title "ExplicitEuler double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SemiImplicitEuler double", \
     $d6 using 1:2 with linespoints dashtype 2 title "ExactBallistic double", \
     $d7 using 1:2 with linespoints dashtype 2 title "Rk4 double"
