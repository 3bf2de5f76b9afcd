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
0.0230369 0.00741112452
0.046645 3.43893524e-05
0.089672 8.07684677e-06
0.180333 1.99479098e-06
0.359962 7.65323639e-07
0.748684 4.95910644e-07
EOD
$d1 << EOD
0.0236307 0.00745545986
0.0470318 3.43893524e-05
0.0930585 8.07684677e-06
0.184219 1.99479098e-06
0.367563 7.65323639e-07
0.770439 4.95910644e-07
EOD
$d2 << EOD
0.0233037 0.00515176261
0.0463008 3.43893524e-05
0.0919822 8.07684677e-06
0.182912 1.99479098e-06
0.361826 7.65323639e-07
0.752795 4.95910644e-07
EOD
$d3 << EOD
0.0228452 0.00741093137
0.0455344 3.40625e-05
0.0893471 8.515625e-06
0.174984 2.12890625e-06
0.349733 5.32226561e-07
0.729138 1.22625002e-07
EOD
$d4 << EOD
0.0232984 0.00745499404
0.0462921 3.40625e-05
0.0916106 8.515625e-06
0.181927 2.12890625e-06
0.363074 5.32226561e-07
0.764103 1.22625002e-07
EOD
$d5 << EOD
0.0234829 0.00515057256
0.0455593 3.40625e-05
0.0898701 8.515625e-06
0.17983 2.12890625e-06
0.356189 5.32226561e-07
0.741896 1.22625002e-07
EOD
plot $d0 using 1:2 with linespoints title "Baumgarte float", \
     $d1 using 1:2 with linespoints title "SplitImpulse float", \
     $d2 using 1:2 with linespoints title "SoftStep float", \
     $d3 using 1:2 with linespoints dashtype 2 title "Baumgarte double", \
     $d4 using 1:2 with linespoints dashtype 2 title "SplitImpulse double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SoftStep double"
