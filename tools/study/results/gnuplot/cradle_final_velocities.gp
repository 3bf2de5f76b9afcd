set terminal pngcairo size 960,600 noenhanced font 'sans,10'
set output 'cradle_final_velocities.png'
set title 'Cradle: final velocity of each ball / v0 (Baumgarte, float)'
set xlabel 'ball (1 = struck first)'
set ylabel 'v / v0 after 1 s'
set grid
set key outside right top
set xtics 1
set xrange [0.5:5.5]
$d0 << EOD
1 -0.00950002372
2 -0.00475001186
3 -0.00475001186
4 0.0190000474
5 1
EOD
$d1 << EOD
1 0
2 0
3 0
4 0
5 1
EOD
$d2 << EOD
1 0
2 0
3 0
4 0
5 1
EOD
$d3 << EOD
1 0
2 0
3 0
4 0
5 1
EOD
$d4 << EOD
1 0
2 0
3 0
4 0
5 1
EOD
$d5 << EOD
1 0
2 0
3 0
4 0
5 1.0000001
EOD
$d6 << EOD
1 0
2 0
3 0
4 0
5 1.00000019
EOD
plot $d0 using 1:2 with linespoints title "Baumgarte 1 iterations", \
     $d1 using 1:2 with linespoints title "Baumgarte 2 iterations", \
     $d2 using 1:2 with linespoints title "Baumgarte 4 iterations", \
     $d3 using 1:2 with linespoints title "Baumgarte 8 iterations", \
     $d4 using 1:2 with linespoints title "Baumgarte 10 iterations", \
     $d5 using 1:2 with linespoints title "Baumgarte 20 iterations", \
     $d6 using 1:2 with linespoints title "Baumgarte 50 iterations"
