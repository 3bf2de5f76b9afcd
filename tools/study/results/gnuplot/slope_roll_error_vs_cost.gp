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
0.0412505 0.0798864125
0.0782135 0.0399447649
0.157369 0.019971843
0.332335 0.00998147118
0.658613 0.00499575655
1.37463 0.00238858258
EOD
$d1 << EOD
0.0382215 0.0798859626
0.0765045 0.0399414227
0.153004 0.0199712712
0.319118 0.00998986186
0.624224 0.00499013401
1.32195 0.00240468073
EOD
$d2 << EOD
0.0388335 0.0798859626
0.0770675 0.0399414227
0.165309 0.0199712712
0.325599 0.00998986186
0.6428 0.00499013401
1.35999 0.00240468073
EOD
$d3 << EOD
0.038698 0.0798859626
0.077481 0.0399414227
0.155979 0.0199712712
0.328736 0.00998986186
0.644449 0.00499013401
1.34397 0.00240468073
EOD
$d4 << EOD
0.0394215 0.0798861335
0.07859 0.0399430667
0.157506 0.0199715334
0.331351 0.00998576668
0.667377 0.00499288334
1.40313 0.002396584
EOD
$d5 << EOD
0.037774 0.0798861335
0.075486 0.0399430667
0.150497 0.0199715334
0.318541 0.00998576668
0.63367 0.00499288334
1.32947 0.002396584
EOD
$d6 << EOD
0.0375255 0.0798861335
0.075354 0.0399430667
0.150163 0.0199715334
0.317603 0.00998576668
0.633048 0.00499288334
1.3296 0.002396584
EOD
$d7 << EOD
0.0378075 0.0798861335
0.075628 0.0399430667
0.150894 0.0199715334
0.343576 0.00998576668
0.634501 0.00499288334
1.33009 0.002396584
EOD
plot $d0 using 1:2 with linespoints title "ExplicitEuler float", \
     $d1 using 1:2 with linespoints title "SemiImplicitEuler float", \
     $d2 using 1:2 with linespoints title "ExactBallistic float", \
     $d3 using 1:2 with linespoints title "Rk4 float", \
     $d4 using 1:2 with linespoints dashtype 2 title "ExplicitEuler double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SemiImplicitEuler double", \
     $d6 using 1:2 with linespoints dashtype 2 title "ExactBallistic double", \
     $d7 using 1:2 with linespoints dashtype 2 title "Rk4 double"
