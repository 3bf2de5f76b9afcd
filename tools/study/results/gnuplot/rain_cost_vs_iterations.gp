set terminal pngcairo size 960,600 noenhanced font 'sans,10'
set output 'rain_cost_vs_iterations.png'
set title 'Rain: ms/step vs iterations (solid) and substeps (points) per position correction'
set xlabel 'iterations (x substeps for the substep sweep at 10 iterations)'
set ylabel 'ms per step'
set grid
set key outside right top
set logscale x
set format x '%g'
set logscale y
set format y '%.0e'
$d0 << EOD
1 1.54812
2 1.53975
4 1.69413
8 1.91834
10 2.07637
20 2.92706
50 5.11627
EOD
$d1 << EOD
1 1.62721
2 1.59399
4 1.82099
8 2.57505
10 2.69954
20 3.70383
50 7.5512
EOD
$d2 << EOD
1 1.62741
2 1.65049
4 2.10691
8 2.17239
10 2.3075
20 3.08896
50 5.32168
EOD
$d3 << EOD
1 1.78959
2 1.987
4 2.25866
8 2.92637
10 3.27828
20 5.27055
50 10.479
EOD
$d4 << EOD
1 1.96787
2 2.05414
4 2.31364
8 3.15672
10 3.65637
20 6.8726
50 14.9496
EOD
$d5 << EOD
1 2.4488
2 2.83955
4 3.17275
8 3.2948
10 3.65148
20 5.44585
50 10.8217
EOD
$d6 << EOD
10 2.07637
20 3.11351
40 5.18094
80 9.44396
EOD
$d7 << EOD
10 2.69954
20 4.01433
40 6.9455
80 12.0371
EOD
$d8 << EOD
10 2.3075
20 3.24337
40 5.44209
80 9.99122
EOD
$d9 << EOD
10 3.27828
20 5.34939
40 9.25801
80 19.8999
EOD
$d10 << EOD
10 3.65637
20 8.09979
40 13.0512
80 19.8779
EOD
$d11 << EOD
10 3.65148
20 5.92441
40 10.1866
80 18.3939
EOD
plot $d0 using 1:2 with linespoints title "Baumgarte float", \
     $d1 using 1:2 with linespoints title "SplitImpulse float", \
     $d2 using 1:2 with linespoints title "SoftStep float", \
     $d3 using 1:2 with linespoints dashtype 2 title "Baumgarte double", \
     $d4 using 1:2 with linespoints dashtype 2 title "SplitImpulse double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SoftStep double", \
     $d6 using 1:2 with points pointsize 1.5 title "Baumgarte float substeps", \
     $d7 using 1:2 with points pointsize 1.5 title "SplitImpulse float substeps", \
     $d8 using 1:2 with points pointsize 1.5 title "SoftStep float substeps", \
     $d9 using 1:2 with points pointsize 1.5 title "Baumgarte double substeps", \
     $d10 using 1:2 with points pointsize 1.5 title "SplitImpulse double substeps", \
     $d11 using 1:2 with points pointsize 1.5 title "SoftStep double substeps"
