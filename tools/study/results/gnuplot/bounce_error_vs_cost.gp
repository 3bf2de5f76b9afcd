set terminal pngcairo size 960,600 noenhanced font 'sans,10'
set output 'bounce_error_vs_cost.png'
set title 'Bounce e = 1: worst apex error over 20 bounces vs cost (dt 1/30 .. 1/1000)'
set xlabel 'ms of World::step per simulated second'
set ylabel 'max |apex - h| / h'
set grid
set key outside right top
set logscale x
set format x '%g'
set logscale y
set format y '%.0e'
$d0 << EOD
0.0163945 0.00741102915
0.032603 3.45800872e-05
0.064851 8.36294906e-06
0.134713 1.99066119e-06
0.269204 5.74588776e-07
0.552239 1.14440918e-07
EOD
$d1 << EOD
0.0174788 0.00745507839
0.0350655 3.45800872e-05
0.0691341 8.36294906e-06
0.138463 1.99066119e-06
0.336707 5.74588776e-07
0.572722 1.14440918e-07
EOD
$d2 << EOD
0.0173091 0.00515149324
0.0335155 3.45800872e-05
0.0655186 8.36294906e-06
0.134001 1.99066119e-06
0.267227 5.74588776e-07
0.555085 1.14440918e-07
EOD
$d3 << EOD
0.0172594 0.00741093137
0.034368 3.40625e-05
0.067839 8.515625e-06
0.136623 2.12890625e-06
0.272057 5.32226561e-07
0.578439 1.22625002e-07
EOD
$d4 << EOD
0.018214 0.00745499404
0.0361815 3.40625e-05
0.0717675 8.515625e-06
0.142498 2.12890625e-06
0.281001 5.32226561e-07
0.589697 1.22625002e-07
EOD
$d5 << EOD
0.0177868 0.00515057256
0.035035 3.40625e-05
0.0696379 8.515625e-06
0.138854 2.12890625e-06
0.277457 5.32226561e-07
0.581483 1.22625002e-07
EOD
plot $d0 using 1:2 with linespoints title "Baumgarte float", \
     $d1 using 1:2 with linespoints title "SplitImpulse float", \
     $d2 using 1:2 with linespoints title "SoftStep float", \
     $d3 using 1:2 with linespoints dashtype 2 title "Baumgarte double", \
     $d4 using 1:2 with linespoints dashtype 2 title "SplitImpulse double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SoftStep double"
