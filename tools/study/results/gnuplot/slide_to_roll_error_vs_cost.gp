set terminal pngcairo size 960,600 noenhanced font 'sans,10'
set output 'slide_to_roll_error_vs_cost.png'
set title 'slide_to_roll: relative error of the final speed vs cost (dt 1/30 .. 1/1000)'
set xlabel 'ms of World::step per simulated second'
set ylabel 'relative error of the final speed'
set grid
set key outside right top
set logscale x
set format x '%g'
set logscale y
set format y '%.0e'
$d0 << EOD
0.0342013 3.43322754e-07
0.0687097 5.24520874e-07
0.135023 1.14440918e-06
0.27298 2.26020813e-06
0.550874 4.19616699e-06
1.14856 2.41279602e-06
EOD
$d1 << EOD
0.033096 3.43322754e-07
0.065365 5.24520874e-07
0.131787 1.14440918e-06
0.264689 2.26020813e-06
0.528764 4.19616699e-06
1.09503 2.41279602e-06
EOD
$d2 << EOD
0.0325243 1.43051148e-07
0.064875 3.9100647e-07
0.130734 1.01089478e-06
0.264791 2.26020813e-06
0.526567 4.19616699e-06
1.10644 2.41279602e-06
EOD
$d3 << EOD
0.03381 1.43051148e-07
0.0674457 3.9100647e-07
0.135524 1.01089478e-06
0.272169 2.26020813e-06
0.538059 4.19616699e-06
1.10444 2.41279602e-06
EOD
$d4 << EOD
0.0343613 6.21724894e-16
0.0681607 4.97379915e-16
0.136169 2.3625546e-15
0.273467 4.1033843e-15
0.544565 7.70938868e-15
1.15698 1.61648472e-14
EOD
$d5 << EOD
0.0335667 6.21724894e-16
0.0671943 4.97379915e-16
0.133413 2.3625546e-15
0.266062 4.1033843e-15
0.531049 7.70938868e-15
1.10514 1.61648472e-14
EOD
$d6 << EOD
0.0332493 2.48689958e-16
0.0658113 2.48689958e-16
0.13078 2.11386464e-15
0.261588 4.1033843e-15
0.528597 7.5850437e-15
1.10903 1.61648472e-14
EOD
$d7 << EOD
0.0332373 2.48689958e-16
0.0666087 2.48689958e-16
0.132905 2.11386464e-15
0.266264 4.1033843e-15
0.526171 7.5850437e-15
1.09397 1.61648472e-14
EOD
plot $d0 using 1:2 with linespoints title "ExplicitEuler float", \
     $d1 using 1:2 with linespoints title "SemiImplicitEuler float", \
     $d2 using 1:2 with linespoints title "ExactBallistic float", \
     $d3 using 1:2 with linespoints title "Rk4 float", \
     $d4 using 1:2 with linespoints dashtype 2 title "ExplicitEuler double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SemiImplicitEuler double", \
     $d6 using 1:2 with linespoints dashtype 2 title "ExactBallistic double", \
     $d7 using 1:2 with linespoints dashtype 2 title "Rk4 double"
