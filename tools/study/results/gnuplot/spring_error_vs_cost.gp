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
0.0234916 335711494
0.0458806 19073.4204
0.0932432 137.810992
0.180169 10.7892813
0.441162 2.43381014
0.952998 0.807893647
EOD
$d1 << EOD
0.021828 0.0552541452
0.0455514 0.0268745202
0.0858653 0.0132667765
0.180498 0.00659565355
0.400799 0.00328616073
0.799144 0.00157828686
EOD
$d2 << EOD
0.0206259 19044.0221
0.0413642 137.790455
0.0833492 10.7891052
0.165025 2.43382074
0.347577 0.853041169
0.75927 0.344598196
EOD
$d3 << EOD
0.0221149 3.35822613e-05
0.0436536 3.8392394e-06
0.0876317 2.23428753e-06
0.173277 5.16636488e-06
0.351071 1.42135253e-06
0.848457 9.31208361e-06
EOD
$d4 << EOD
0.0292251 335711021
0.0580716 19073.3549
0.116194 137.810798
0.237735 10.7892693
0.468427 2.43382269
0.970991 0.807913362
EOD
$d5 << EOD
0.0275264 0.0552528647
0.0557835 0.0268744013
0.111488 0.0132624445
0.221299 0.0065879621
0.441598 0.0032832191
0.928722 0.00157326567
EOD
$d6 << EOD
0.0278333 19043.9709
0.055688 137.790894
0.111302 10.7890617
0.22155 2.43381513
0.445947 0.853075511
0.926473 0.344588121
EOD
$d7 << EOD
0.0300647 3.29237156e-05
0.0433273 1.02994173e-06
0.0859225 3.21939635e-08
0.172992 1.00612007e-09
0.344727 3.14397166e-11
0.763235 7.80044491e-13
EOD
plot $d0 using 1:2 with linespoints title "ExplicitEuler float", \
     $d1 using 1:2 with linespoints title "SemiImplicitEuler float", \
     $d2 using 1:2 with linespoints title "ExactBallistic float", \
     $d3 using 1:2 with linespoints title "Rk4 float", \
     $d4 using 1:2 with linespoints dashtype 2 title "ExplicitEuler double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SemiImplicitEuler double", \
     $d6 using 1:2 with linespoints dashtype 2 title "ExactBallistic double", \
     $d7 using 1:2 with linespoints dashtype 2 title "Rk4 double"
