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
0.0397513 3.43322754e-07
0.0787677 5.24520874e-07
0.167939 1.14440918e-06
0.326508 2.26020813e-06
0.655994 4.19616699e-06
1.36814 2.41279602e-06
EOD
$d1 << EOD
0.0385103 3.43322754e-07
0.0763583 5.24520874e-07
0.162405 1.14440918e-06
0.320171 2.26020813e-06
0.640296 4.19616699e-06
1.31583 2.41279602e-06
EOD
$d2 << EOD
0.037496 3.43322754e-07
0.0747653 5.24520874e-07
0.153501 1.14440918e-06
0.311548 2.26020813e-06
0.629503 4.19616699e-06
1.30222 2.41279602e-06
EOD
$d3 << EOD
0.0379103 3.43322754e-07
0.075495 5.24520874e-07
0.153703 1.14440918e-06
0.323961 2.26020813e-06
0.626959 4.19616699e-06
1.33462 2.41279602e-06
EOD
$d4 << EOD
0.039795 6.21724894e-16
0.0789447 4.97379915e-16
0.169577 2.3625546e-15
0.335688 4.1033843e-15
0.684879 7.70938868e-15
1.42414 1.61648472e-14
EOD
$d5 << EOD
0.0374857 6.21724894e-16
0.0828457 4.97379915e-16
0.161449 2.3625546e-15
0.315419 4.1033843e-15
0.633907 7.70938868e-15
1.31987 1.61648472e-14
EOD
$d6 << EOD
0.0377367 6.21724894e-16
0.0753167 4.97379915e-16
0.162248 2.3625546e-15
0.310906 4.1033843e-15
0.62937 7.70938868e-15
1.34121 1.61648472e-14
EOD
$d7 << EOD
0.048863 6.21724894e-16
0.100101 4.97379915e-16
0.208919 2.3625546e-15
0.331362 4.1033843e-15
0.640623 7.70938868e-15
1.3265 1.61648472e-14
EOD
plot $d0 using 1:2 with linespoints title "ExplicitEuler float", \
     $d1 using 1:2 with linespoints title "SemiImplicitEuler float", \
     $d2 using 1:2 with linespoints title "ExactBallistic float", \
     $d3 using 1:2 with linespoints title "Rk4 float", \
     $d4 using 1:2 with linespoints dashtype 2 title "ExplicitEuler double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SemiImplicitEuler double", \
     $d6 using 1:2 with linespoints dashtype 2 title "ExactBallistic double", \
     $d7 using 1:2 with linespoints dashtype 2 title "Rk4 double"
