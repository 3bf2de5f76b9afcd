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
1 1.38497
2 1.4527
4 1.59936
8 1.8431
10 1.96701
20 2.65087
50 4.73005
EOD
$d1 << EOD
1 1.4334
2 1.53648
4 1.77142
8 2.13202
10 2.32244
20 3.38087
50 6.48431
EOD
$d2 << EOD
1 1.48744
2 1.50453
4 1.69375
8 1.88369
10 2.0265
20 2.69898
50 4.69447
EOD
$d3 << EOD
1 1.71163
2 1.78888
4 2.08589
8 2.74608
10 3.07158
20 4.67805
50 9.34364
EOD
$d4 << EOD
1 1.67669
2 1.8372
4 2.20634
8 2.97989
10 3.31098
20 5.17765
50 10.7578
EOD
$d5 << EOD
1 1.77379
2 1.93761
4 2.23915
8 2.82482
10 3.15462
20 4.76636
50 9.46899
EOD
$d6 << EOD
10 1.96701
20 2.96946
40 4.83422
80 8.7658
EOD
$d7 << EOD
10 2.32244
20 3.80757
40 6.53955
80 11.6291
EOD
$d8 << EOD
10 2.0265
20 3.07596
40 5.14805
80 9.28521
EOD
$d9 << EOD
10 3.07158
20 4.95489
40 8.58289
80 15.864
EOD
$d10 << EOD
10 3.31098
20 5.60596
40 10.1622
80 19.4753
EOD
$d11 << EOD
10 3.15462
20 5.32835
40 9.38169
80 17.5305
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
