set terminal pngcairo size 960,600 noenhanced font 'sans,10'
set output 'spring_error_vs_cost.png'
set title 'spring: worst energy error over 60 s vs cost (dt 1/30 .. 1/1000)'
set xlabel 'ms of World::step per simulated second'
set ylabel 'max |dE / E0| over 60 s'
set grid
set key outside right top
set logscale x
set format x '%g'
set logscale y
set format y '%.0e'
$d0 << EOD
0.023933 335711494
0.0477485 19073.4204
0.0954362 137.810992
0.191545 10.7892813
0.383916 2.43381014
0.791388 0.807893647
EOD
$d1 << EOD
0.0222002 0.0552541452
0.0443071 0.0268745202
0.0888515 0.0132667765
0.1771 0.00659565355
0.353507 0.00328616073
0.743699 0.00157828686
EOD
$d2 << EOD
0.0223545 0.0523610171
0.0446611 0.0261813511
0.0886266 0.0130933799
0.177704 0.00655029791
0.35619 0.00327763149
0.741361 0.00157583514
EOD
$d3 << EOD
0.0235651 3.35822613e-05
0.0468918 3.8392394e-06
0.0944604 2.23428753e-06
0.188317 5.16636488e-06
0.376589 1.42135253e-06
0.78523 9.31208361e-06
EOD
$d4 << EOD
0.0238111 335711021
0.0475877 19073.3549
0.094595 137.810798
0.189867 10.7892693
0.382613 2.43382269
0.788987 0.807913362
EOD
$d5 << EOD
0.0223171 0.0552528647
0.0445099 0.0268744013
0.0889138 0.0132624445
0.177505 0.0065879621
0.355383 0.0032832191
0.740418 0.00157326567
EOD
$d6 << EOD
0.0224774 0.0523598762
0.0446525 0.0261799385
0.0891771 0.0130899327
0.178995 0.00654493582
0.357916 0.00327248127
0.744541 0.00157079475
EOD
$d7 << EOD
0.0235698 3.29237156e-05
0.0469127 1.02994173e-06
0.0942137 3.21939635e-08
0.188424 1.00612007e-09
0.376999 3.14397166e-11
0.796182 7.80044491e-13
EOD
plot $d0 using 1:2 with linespoints title "ExplicitEuler float", \
     $d1 using 1:2 with linespoints title "SemiImplicitEuler float", \
     $d2 using 1:2 with linespoints title "ExactBallistic float", \
     $d3 using 1:2 with linespoints title "Rk4 float", \
     $d4 using 1:2 with linespoints dashtype 2 title "ExplicitEuler double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SemiImplicitEuler double", \
     $d6 using 1:2 with linespoints dashtype 2 title "ExactBallistic double", \
     $d7 using 1:2 with linespoints dashtype 2 title "Rk4 double"
