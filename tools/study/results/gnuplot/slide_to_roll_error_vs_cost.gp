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
0.0548897 3.43322754e-07
0.089911 5.24520874e-07
0.205768 1.14440918e-06
0.386179 2.26020813e-06
0.75708 4.19616699e-06
1.57201 2.41279602e-06
EOD
$d1 << EOD
0.040692 3.43322754e-07
0.090599 5.24520874e-07
0.184398 1.14440918e-06
0.35119 2.26020813e-06
0.706793 4.19616699e-06
1.46134 2.41279602e-06
EOD
$d2 << EOD
0.0449823 1.43051148e-07
0.0886903 3.9100647e-07
0.181694 1.01089478e-06
0.375123 2.26020813e-06
0.817595 4.19616699e-06
1.53865 2.41279602e-06
EOD
$d3 << EOD
0.0400333 1.43051148e-07
0.0814163 3.9100647e-07
0.180461 1.01089478e-06
0.375138 2.26020813e-06
0.745098 4.19616699e-06
1.49061 2.41279602e-06
EOD
$d4 << EOD
0.041527 6.21724894e-16
0.083061 4.97379915e-16
0.177032 2.3625546e-15
0.356612 4.1033843e-15
0.715249 7.70938868e-15
1.47433 1.61648472e-14
EOD
$d5 << EOD
0.0404467 6.21724894e-16
0.0810257 4.97379915e-16
0.17408 2.3625546e-15
0.336077 4.1033843e-15
0.676813 7.70938868e-15
1.41175 1.61648472e-14
EOD
$d6 << EOD
0.0405787 2.48689958e-16
0.0812283 2.48689958e-16
0.174424 2.11386464e-15
0.343306 4.1033843e-15
0.679837 7.5850437e-15
1.41763 1.61648472e-14
EOD
$d7 << EOD
0.039898 2.48689958e-16
0.0899163 2.48689958e-16
0.171391 2.11386464e-15
0.331896 4.1033843e-15
0.676936 7.5850437e-15
1.41826 1.61648472e-14
EOD
plot $d0 using 1:2 with linespoints title "ExplicitEuler float", \
     $d1 using 1:2 with linespoints title "SemiImplicitEuler float", \
     $d2 using 1:2 with linespoints title "ExactBallistic float", \
     $d3 using 1:2 with linespoints title "Rk4 float", \
     $d4 using 1:2 with linespoints dashtype 2 title "ExplicitEuler double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SemiImplicitEuler double", \
     $d6 using 1:2 with linespoints dashtype 2 title "ExactBallistic double", \
     $d7 using 1:2 with linespoints dashtype 2 title "Rk4 double"
