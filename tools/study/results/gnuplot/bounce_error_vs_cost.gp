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
0.0270925 0.736220168
0.0427716 0.557323319
0.084569 0.313167108
0.170192 0.160387461
0.341427 0.0838617426
0.709485 0.0358376983
EOD
$d1 << EOD
0.0230391 0.736220168
0.0448518 0.557323319
0.0874778 0.313167108
0.173684 0.160387461
0.346443 0.0838617426
0.72407 0.0358376983
EOD
$d2 << EOD
0.0222808 0.803255261
0.0442214 0.557323319
0.0865709 0.313167108
0.170438 0.160387461
0.346715 0.0838617426
0.707625 0.0358376983
EOD
$d3 << EOD
0.0222258 0.73622
0.0431713 0.55732375
0.0842368 0.379210937
0.166369 0.176360234
0.333732 0.083855
0.690067 0.0399929095
EOD
$d4 << EOD
0.0223164 0.73622
0.0435237 0.55732375
0.0848173 0.379210937
0.169786 0.176360234
0.341881 0.083855
0.705756 0.0399929095
EOD
$d5 << EOD
0.0218194 0.803255
0.0528246 0.55732375
0.0834925 0.379210937
0.166584 0.176360234
0.330947 0.083855
0.690409 0.0399929095
EOD
plot $d0 using 1:2 with linespoints title "Baumgarte float", \
     $d1 using 1:2 with linespoints title "SplitImpulse float", \
     $d2 using 1:2 with linespoints title "SoftStep float", \
     $d3 using 1:2 with linespoints dashtype 2 title "Baumgarte double", \
     $d4 using 1:2 with linespoints dashtype 2 title "SplitImpulse double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SoftStep double"
