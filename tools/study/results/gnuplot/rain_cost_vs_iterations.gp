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
1 1.2503
2 1.25393
4 1.37119
8 1.60232
10 1.70695
20 2.36557
50 4.14472
EOD
$d1 << EOD
1 1.44628
2 1.40544
4 1.55049
8 1.92983
10 2.11907
20 3.00291
50 5.63656
EOD
$d2 << EOD
1 1.29866
2 1.34334
4 1.45959
8 1.93214
10 1.82442
20 2.43318
50 4.07738
EOD
$d3 << EOD
1 1.8098
2 1.80607
4 2.20186
8 2.42251
10 2.6097
20 3.92903
50 7.8088
EOD
$d4 << EOD
1 1.54948
2 1.6422
4 2.05827
8 2.68602
10 4.76865
20 8.16802
50 15.7408
EOD
$d5 << EOD
1 3.12867
2 3.28559
4 3.45634
8 3.38376
10 3.16392
20 4.14716
50 7.90401
EOD
$d6 << EOD
10 1.70695
20 2.59397
40 4.27994
80 7.37835
EOD
$d7 << EOD
10 2.11907
20 3.24707
40 5.36982
80 10.1153
EOD
$d8 << EOD
10 1.82442
20 2.69329
40 4.49944
80 7.73598
EOD
$d9 << EOD
10 2.6097
20 4.02975
40 7.15725
80 13.2203
EOD
$d10 << EOD
10 4.76865
20 4.84857
40 8.31478
80 15.6087
EOD
$d11 << EOD
10 3.16392
20 4.54503
40 7.94006
80 14.579
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
