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
0.0229534 0.00741112452
0.0455959 3.43893524e-05
0.0906707 8.07684677e-06
0.180567 1.99479098e-06
0.359871 7.65323639e-07
0.755506 4.95910644e-07
EOD
$d1 << EOD
0.0237375 0.00745545986
0.0470001 3.43893524e-05
0.0928415 8.07684677e-06
0.184579 1.99479098e-06
0.367878 7.65323639e-07
0.782416 4.95910644e-07
EOD
$d2 << EOD
0.0232208 0.00515176261
0.0459604 3.43893524e-05
0.0911497 8.07684677e-06
0.182171 1.99479098e-06
0.363494 7.65323639e-07
0.757839 4.95910644e-07
EOD
$d3 << EOD
0.0233728 0.00741093137
0.0464582 3.40625e-05
0.0929252 8.515625e-06
0.18686 2.12890625e-06
0.362506 5.32226561e-07
0.760944 1.22625002e-07
EOD
$d4 << EOD
0.0238594 0.00745499404
0.0468278 3.40625e-05
0.0954534 8.515625e-06
0.189253 2.12890625e-06
0.3673 5.32226561e-07
0.796942 1.22625002e-07
EOD
$d5 << EOD
0.0236098 0.00515057256
0.0464047 3.40625e-05
0.09158 8.515625e-06
0.186003 2.12890625e-06
0.370249 5.32226561e-07
0.769589 1.22625002e-07
EOD
plot $d0 using 1:2 with linespoints title "Baumgarte float", \
     $d1 using 1:2 with linespoints title "SplitImpulse float", \
     $d2 using 1:2 with linespoints title "SoftStep float", \
     $d3 using 1:2 with linespoints dashtype 2 title "Baumgarte double", \
     $d4 using 1:2 with linespoints dashtype 2 title "SplitImpulse double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SoftStep double"
