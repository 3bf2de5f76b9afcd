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
0.033395 0.0798864125
0.066784 0.0399447649
0.133958 0.019971843
0.269122 0.00998147118
0.547016 0.00499575655
1.13722 0.00238858258
EOD
$d1 << EOD
0.032874 0.0798859626
0.0650105 0.0399414227
0.129795 0.0199712712
0.260644 0.00998986186
0.524315 0.00499013401
1.10279 0.00240468073
EOD
$d2 << EOD
0.0328685 2.2492203e-07
0.065748 3.04702285e-07
0.132347 3.87598541e-07
0.263077 1.03818649e-06
0.525651 2.99400724e-06
1.10694 1.52191836e-05
EOD
$d3 << EOD
0.0325235 2.2492203e-07
0.065158 3.04702285e-07
0.131361 3.87598541e-07
0.265466 1.03818649e-06
0.531356 2.99400724e-06
1.09664 1.52191836e-05
EOD
$d4 << EOD
0.0339395 0.0798861335
0.0674305 0.0399430667
0.135637 0.0199715334
0.272407 0.00998576668
0.54163 0.00499288334
1.15187 0.002396584
EOD
$d5 << EOD
0.032493 0.0798861335
0.0647565 0.0399430667
0.128401 0.0199715334
0.255351 0.00998576668
0.513674 0.00499288334
1.08277 0.002396584
EOD
$d6 << EOD
0.0329645 4.4408921e-15
0.065547 1.77635684e-15
0.130148 8.8817842e-15
0.26158 1.0658141e-14
0.531512 7.10542736e-15
1.10577 3.28626015e-14
EOD
$d7 << EOD
0.0332455 4.4408921e-15
0.066461 1.77635684e-15
0.132953 8.8817842e-15
0.264586 1.0658141e-14
0.526837 7.10542736e-15
1.09824 3.28626015e-14
EOD
plot $d0 using 1:2 with linespoints title "ExplicitEuler float", \
     $d1 using 1:2 with linespoints title "SemiImplicitEuler float", \
     $d2 using 1:2 with linespoints title "ExactBallistic float", \
     $d3 using 1:2 with linespoints title "Rk4 float", \
     $d4 using 1:2 with linespoints dashtype 2 title "ExplicitEuler double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SemiImplicitEuler double", \
     $d6 using 1:2 with linespoints dashtype 2 title "ExactBallistic double", \
     $d7 using 1:2 with linespoints dashtype 2 title "Rk4 double"
