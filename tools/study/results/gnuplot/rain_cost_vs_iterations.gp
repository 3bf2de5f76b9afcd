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
1 1.56556
2 1.62472
4 1.77814
8 2.05419
10 2.16126
20 2.65871
50 4.77501
EOD
$d1 << EOD
1 1.44495
2 1.53036
4 1.73863
8 2.11068
10 2.64248
20 4.48756
50 8.45451
EOD
$d2 << EOD
1 1.44075
2 1.51746
4 1.89808
8 2.29103
10 2.39095
20 2.65243
50 4.79083
EOD
$d3 << EOD
1 2.23697
2 2.32963
4 2.67187
8 3.36631
10 3.6465
20 5.44945
50 10.0541
EOD
$d4 << EOD
1 1.78533
2 2.12413
4 2.43644
8 3.14842
10 3.78725
20 5.45322
50 12.1576
EOD
$d5 << EOD
1 2.46201
2 2.29061
4 2.44553
8 3.00073
10 3.33573
20 5.56209
50 10.6451
EOD
$d6 << EOD
10 2.16126
20 2.93322
40 4.90109
80 8.76388
EOD
$d7 << EOD
10 2.64248
20 3.67754
40 6.29892
80 11.4739
EOD
$d8 << EOD
10 2.39095
20 3.09645
40 5.16543
80 9.56055
EOD
$d9 << EOD
10 3.6465
20 5.77149
40 9.18724
80 17.5466
EOD
$d10 << EOD
10 3.78725
20 6.18063
40 10.8462
80 20.3571
EOD
$d11 << EOD
10 3.33573
20 5.97019
40 10.4716
80 20.3469
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
