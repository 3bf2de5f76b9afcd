set terminal pngcairo size 960,600 noenhanced font 'sans,10'
set output 'slope_roll_error_vs_cost.png'
set title 'slope_roll: position error after 2 s, m vs cost (dt 1/30 .. 1/1000)'
set xlabel 'ms of World::step per simulated second'
set ylabel 'position error after 2 s, m'
set grid
set key outside right top
set logscale x
set format x '%g'
set logscale y
set format y '%.0e'
$d0 << EOD
0.0406905 0.0798864125
0.08174 0.0399447649
0.162785 0.019971843
0.343921 0.00998147118
0.682418 0.00499575655
1.44105 0.00238858258
EOD
$d1 << EOD
0.0398475 0.0798859626
0.0797625 0.0399414227
0.159446 0.0199712712
0.334494 0.00998986186
0.661581 0.00499013401
1.41398 0.00240468073
EOD
$d2 << EOD
0.0397475 2.2492203e-07
0.0794935 3.04702285e-07
0.159095 3.87598541e-07
0.334689 1.03818649e-06
0.667407 2.99400724e-06
1.39474 1.52191836e-05
EOD
$d3 << EOD
0.0398065 2.2492203e-07
0.0795475 3.04702285e-07
0.158724 3.87598541e-07
0.334887 1.03818649e-06
0.664508 2.99400724e-06
1.39473 1.52191836e-05
EOD
$d4 << EOD
0.041573 0.0798861335
0.082898 0.0399430667
0.165892 0.0199715334
0.348433 0.00998576668
0.697075 0.00499288334
1.44993 0.002396584
EOD
$d5 << EOD
0.040143 0.0798861335
0.080407 0.0399430667
0.160366 0.0199715334
0.337808 0.00998576668
0.673559 0.00499288334
1.40218 0.002396584
EOD
$d6 << EOD
0.0402995 4.4408921e-15
0.0805785 1.77635684e-15
0.160784 8.8817842e-15
0.33863 1.0658141e-14
0.677298 7.10542736e-15
1.41499 3.28626015e-14
EOD
$d7 << EOD
0.04071 4.4408921e-15
0.0813065 1.77635684e-15
0.16315 8.8817842e-15
0.342458 1.0658141e-14
0.686118 7.10542736e-15
1.42515 3.28626015e-14
EOD
plot $d0 using 1:2 with linespoints title "ExplicitEuler float", \
     $d1 using 1:2 with linespoints title "SemiImplicitEuler float", \
     $d2 using 1:2 with linespoints title "ExactBallistic float", \
     $d3 using 1:2 with linespoints title "Rk4 float", \
     $d4 using 1:2 with linespoints dashtype 2 title "ExplicitEuler double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SemiImplicitEuler double", \
     $d6 using 1:2 with linespoints dashtype 2 title "ExactBallistic double", \
     $d7 using 1:2 with linespoints dashtype 2 title "Rk4 double"
