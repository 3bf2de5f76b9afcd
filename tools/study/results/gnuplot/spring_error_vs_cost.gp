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
0.0179279 335711494
0.0357505 19073.4204
0.0689923 137.810992
0.141867 10.7892813
0.278759 2.43381014
0.590708 0.807893647
EOD
$d1 << EOD
0.0162014 0.0552541452
0.032268 0.0268745202
0.0639963 0.0132667765
0.12894 0.00659565355
0.262265 0.00328616073
0.548222 0.00157828686
EOD
$d2 << EOD
0.0164641 0.0523610171
0.0330951 0.0261813511
0.0663444 0.0130933799
0.134057 0.00655029791
0.270285 0.00327763149
0.558032 0.00157583514
EOD
$d3 << EOD
0.0172536 3.35822613e-05
0.0345719 3.8392394e-06
0.0690606 2.23428753e-06
0.134702 5.16636488e-06
0.278631 1.42135253e-06
0.592642 9.31208361e-06
EOD
$d4 << EOD
0.0183507 335711021
0.0372918 19073.3549
0.0747361 137.810798
0.150209 10.7892693
0.294529 2.43382269
0.610544 0.807913362
EOD
$d5 << EOD
0.0169296 0.0552528647
0.0336832 0.0268744013
0.0679603 0.0132624445
0.136711 0.0065879621
0.274001 0.0032832191
0.579427 0.00157326567
EOD
$d6 << EOD
0.0176627 0.0523598762
0.0355651 0.0261799385
0.0702549 0.0130899327
0.140593 0.00654493582
0.281304 0.00327248127
0.594143 0.00157079475
EOD
$d7 << EOD
0.0183561 3.29237156e-05
0.036855 1.02994173e-06
0.0726253 3.21939635e-08
0.144885 1.00612007e-09
0.286315 3.14397166e-11
0.59739 7.80044491e-13
EOD
plot $d0 using 1:2 with linespoints title "ExplicitEuler float", \
     $d1 using 1:2 with linespoints title "SemiImplicitEuler float", \
     $d2 using 1:2 with linespoints title "ExactBallistic float", \
     $d3 using 1:2 with linespoints title "Rk4 float", \
     $d4 using 1:2 with linespoints dashtype 2 title "ExplicitEuler double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SemiImplicitEuler double", \
     $d6 using 1:2 with linespoints dashtype 2 title "ExactBallistic double", \
     $d7 using 1:2 with linespoints dashtype 2 title "Rk4 double"
