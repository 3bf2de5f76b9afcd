set terminal pngcairo size 960,600 noenhanced font 'sans,10'
set output 'rain_penetration_vs_cost.png'
set title 'Rain: max penetration vs ms/step, iterations 1..50 per position correction'
set xlabel 'ms per step'
set ylabel 'max penetration, m'
set grid
set key outside right top
set logscale x
set format x '%g'
set logscale y
set format y '%.0e'
$d0 << EOD
1.54812 0.169998005
1.53975 0.126503892
1.69413 0.0610390019
1.91834 0.0368041424
2.07637 0.0298308546
2.92706 0.0151538671
5.11627 0.00701439783
EOD
$d1 << EOD
1.62721 0.23348405
1.59399 0.139993304
1.82099 0.0537863758
2.57505 0.0393341451
2.69954 0.033013616
3.70383 0.0184624296
7.5512 0.00670944729
EOD
$d2 << EOD
1.62741 0.16842338
1.65049 0.106026977
2.10691 0.0976676056
2.17239 0.0909702719
2.3075 0.11262031
3.08896 0.0884384133
5.32168 0.0950397599
EOD
$d3 << EOD
1.78959 0.155979329
1.987 0.113728237
2.25866 0.0631500548
2.92637 0.0443557244
3.27828 0.0334166212
5.27055 0.0164967306
10.479 0.00584253804
EOD
$d4 << EOD
1.96787 0.22660751
2.05414 0.13234515
2.31364 0.0613931433
3.15672 0.0396084879
3.65637 0.0294630783
6.8726 0.0150128423
14.9496 0.006885619
EOD
$d5 << EOD
2.4488 0.150874398
2.83955 0.132028864
3.17275 0.0947993109
3.2948 0.098639933
3.65148 0.0949460575
5.44585 0.0935870488
10.8217 0.122280581
EOD
plot $d0 using 1:2 with linespoints title "Baumgarte float", \
     $d1 using 1:2 with linespoints title "SplitImpulse float", \
     $d2 using 1:2 with linespoints title "SoftStep float", \
     $d3 using 1:2 with linespoints dashtype 2 title "Baumgarte double", \
     $d4 using 1:2 with linespoints dashtype 2 title "SplitImpulse double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SoftStep double"
