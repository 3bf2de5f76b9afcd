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
1.2503 0.54712443
1.25393 0.537371866
1.37119 0.321879251
1.60232 0.224823005
1.70695 0.191737449
2.36557 0.123595573
4.14472 0.0356640988
EOD
$d1 << EOD
1.44628 0.973681204
1.40544 0.797247767
1.55049 0.487347755
1.92983 0.280870885
2.11907 0.178388166
3.00291 0.0901251395
5.63656 0.0327547258
EOD
$d2 << EOD
1.29866 0.649515093
1.34334 0.550175493
1.45959 0.491920455
1.93214 0.354159127
1.82442 0.291441893
2.43318 0.236877851
4.07738 0.174278222
EOD
$d3 << EOD
1.8098 0.469941537
1.80607 0.529722578
2.20186 0.272676611
2.42251 0.216962974
2.6097 0.188305618
3.92903 0.122223591
7.8088 0.0344080535
EOD
$d4 << EOD
1.54948 0.989590176
1.6422 0.745508355
2.05827 0.510000439
2.68602 0.223591232
4.76865 0.189511072
8.16802 0.0868065007
15.7408 0.0468939273
EOD
$d5 << EOD
3.12867 0.63897158
3.28559 0.615098447
3.45634 0.549554601
3.38376 0.365416508
3.16392 0.302058454
4.14716 0.202727013
7.90401 0.143492536
EOD
plot $d0 using 1:2 with linespoints title "Baumgarte float", \
     $d1 using 1:2 with linespoints title "SplitImpulse float", \
     $d2 using 1:2 with linespoints title "SoftStep float", \
     $d3 using 1:2 with linespoints dashtype 2 title "Baumgarte double", \
     $d4 using 1:2 with linespoints dashtype 2 title "SplitImpulse double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SoftStep double"
