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
0.0411347 3.43322754e-07
0.0823637 5.24520874e-07
0.177705 1.14440918e-06
0.459545 2.26020813e-06
0.705287 4.19616699e-06
1.44808 2.41279602e-06
EOD
$d1 << EOD
0.039635 3.43322754e-07
0.0792767 5.24520874e-07
0.170613 1.14440918e-06
0.331604 2.26020813e-06
0.679984 4.19616699e-06
1.43663 2.41279602e-06
EOD
$d2 << EOD
0.040393 1.43051148e-07
0.0822357 3.9100647e-07
0.170573 1.01089478e-06
0.336802 2.26020813e-06
0.682573 4.19616699e-06
1.42418 2.41279602e-06
EOD
$d3 << EOD
0.040267 1.43051148e-07
0.079867 3.9100647e-07
0.172048 1.01089478e-06
0.335487 2.26020813e-06
0.675449 4.19616699e-06
1.40795 2.41279602e-06
EOD
$d4 << EOD
0.0421253 6.21724894e-16
0.0839487 4.97379915e-16
0.179629 2.3625546e-15
0.348791 4.1033843e-15
0.700814 7.70938868e-15
1.46211 1.61648472e-14
EOD
$d5 << EOD
0.0406213 6.21724894e-16
0.0818927 4.97379915e-16
0.173872 2.3625546e-15
0.337679 4.1033843e-15
0.682156 7.70938868e-15
1.42127 1.61648472e-14
EOD
$d6 << EOD
0.040545 2.48689958e-16
0.0811243 2.48689958e-16
0.173297 2.11386464e-15
0.337141 4.1033843e-15
0.680241 7.5850437e-15
1.41281 1.61648472e-14
EOD
$d7 << EOD
0.040876 2.48689958e-16
0.0816997 2.48689958e-16
0.174246 2.11386464e-15
0.337525 4.1033843e-15
0.687243 7.5850437e-15
1.42896 1.61648472e-14
EOD
plot $d0 using 1:2 with linespoints title "ExplicitEuler float", \
     $d1 using 1:2 with linespoints title "SemiImplicitEuler float", \
     $d2 using 1:2 with linespoints title "ExactBallistic float", \
     $d3 using 1:2 with linespoints title "Rk4 float", \
     $d4 using 1:2 with linespoints dashtype 2 title "ExplicitEuler double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SemiImplicitEuler double", \
     $d6 using 1:2 with linespoints dashtype 2 title "ExactBallistic double", \
     $d7 using 1:2 with linespoints dashtype 2 title "Rk4 double"
