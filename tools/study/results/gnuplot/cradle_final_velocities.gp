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
1 -0.625859261
2 -0.271998453
3 0
4 0.800158691
5 1.09769945
EOD
$d1 << EOD
1 -0.0625000238
2 -0.0625000238
3 -0.0657184601
4 0.59535923
5 0.59535923
EOD
$d2 << EOD
1 -0.218749738
2 0
3 0.120216465
4 0.415817213
5 0.682716084
EOD
$d3 << EOD
1 -0.248046684
2 0
3 0.16404295
4 0.416054821
5 0.667948961
EOD
$d4 << EOD
1 -0.249511456
2 0
3 0.166014481
4 0.416506338
5 0.6669909
EOD
$d5 << EOD
1 -0.249999142
2 0
3 0.166667128
4 0.4166646
5 0.666667843
EOD
$d6 << EOD
1 -0.249999642
2 0
3 0.166667795
4 0.416664839
5 0.666667509
EOD
plot $d0 using 1:2 with linespoints title "Baumgarte 1 iterations", \
     $d1 using 1:2 with linespoints title "Baumgarte 2 iterations", \
     $d2 using 1:2 with linespoints title "Baumgarte 4 iterations", \
     $d3 using 1:2 with linespoints title "Baumgarte 8 iterations", \
     $d4 using 1:2 with linespoints title "Baumgarte 10 iterations", \
     $d5 using 1:2 with linespoints title "Baumgarte 20 iterations", \
     $d6 using 1:2 with linespoints title "Baumgarte 50 iterations"
