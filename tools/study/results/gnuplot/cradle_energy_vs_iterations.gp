set terminal pngcairo size 960,600 noenhanced font 'sans,10'
set output 'cradle_energy_vs_iterations.png'
set title 'Cradle: kinetic energy fraction reaching the last ball vs iterations'
set xlabel 'solver iterations'
set ylabel 'KE of last ball / initial KE'
set grid
set key outside right top
set logscale x
set format x '%g'
set yrange [0:1.05]
$d0 << EOD
1 1
2 1
4 1
8 1
10 1
20 1.00000019
50 1.00000038
EOD
$d1 << EOD
1 1
2 1
4 1
8 1
10 1
20 1.00000019
50 1.00000038
EOD
$d2 << EOD
1 1
2 1
4 1
8 1
10 1
20 1
50 1
EOD
$d3 << EOD
1 1
2 1
4 1
8 1
10 1
20 1
50 1
EOD
$d4 << EOD
1 1
2 1
4 1
8 1
10 1
20 1
50 1
EOD
$d5 << EOD
1 1
2 1
4 1
8 1
10 1
20 1
50 1
EOD
plot $d0 using 1:2 with linespoints title "Baumgarte float", \
     $d1 using 1:2 with linespoints title "SplitImpulse float", \
     $d2 using 1:2 with linespoints title "SoftStep float", \
     $d3 using 1:2 with linespoints dashtype 2 title "Baumgarte double", \
     $d4 using 1:2 with linespoints dashtype 2 title "SplitImpulse double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SoftStep double"
