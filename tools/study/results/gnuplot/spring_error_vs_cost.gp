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
0.0239512 335711494
0.0479417 19073.4204
0.0969207 137.810992
0.243072 10.7892813
0.382036 2.43381014
0.790787 0.807893647
EOD
$d1 << EOD
0.0219218 0.0552541452
0.0445896 0.0268745202
0.0894309 0.0132667765
0.177773 0.00659565355
0.355583 0.00328616073
0.743615 0.00157828686
EOD
$d2 << EOD
0.0219107 0.0523610171
0.0441304 0.0261813511
0.0882058 0.0130933799
0.176079 0.00655029791
0.354785 0.00327763149
0.735193 0.00157583514
EOD
$d3 << EOD
0.0229192 3.35822613e-05
0.0466926 3.8392394e-06
0.0935046 2.23428753e-06
0.186572 5.16636488e-06
0.380098 1.42135253e-06
0.77925 9.31208361e-06
EOD
$d4 << EOD
0.0241625 335711021
0.0482745 19073.3549
0.0973634 137.810798
0.19286 10.7892693
0.391201 2.43382269
0.832273 0.807913362
EOD
$d5 << EOD
0.0229701 0.0552528647
0.0452903 0.0268744013
0.0902157 0.0132624445
0.180102 0.0065879621
0.365849 0.0032832191
0.749767 0.00157326567
EOD
$d6 << EOD
0.0227856 0.0523598762
0.0455614 0.0261799385
0.0929679 0.0130899327
0.182753 0.00654493582
0.366791 0.00327248127
0.762023 0.00157079475
EOD
$d7 << EOD
0.0239023 3.29237156e-05
0.0478161 1.02994173e-06
0.0952652 3.21939635e-08
0.190735 1.00612007e-09
0.383856 3.14397166e-11
0.805302 7.80044491e-13
EOD
plot $d0 using 1:2 with linespoints title "ExplicitEuler float", \
     $d1 using 1:2 with linespoints title "SemiImplicitEuler float", \
     $d2 using 1:2 with linespoints title "ExactBallistic float", \
     $d3 using 1:2 with linespoints title "Rk4 float", \
     $d4 using 1:2 with linespoints dashtype 2 title "ExplicitEuler double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SemiImplicitEuler double", \
     $d6 using 1:2 with linespoints dashtype 2 title "ExactBallistic double", \
     $d7 using 1:2 with linespoints dashtype 2 title "Rk4 double"
