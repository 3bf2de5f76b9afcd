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
1.38497 0.145856865
1.4527 0.1108183
1.59936 0.0593302225
1.8431 0.0359545378
1.96701 0.0267508195
2.65087 0.0198719119
4.73005 0.00718087932
EOD
$d1 << EOD
1.4334 0.178714659
1.53648 0.124319239
1.77142 0.0560375987
2.13202 0.0370246868
2.32244 0.0402338725
3.38087 0.0162566953
6.48431 0.0316833496
EOD
$d2 << EOD
1.48744 0.134510017
1.50453 0.0965361185
1.69375 0.091940084
1.88369 0.0926571948
2.0265 0.0936472196
2.69898 0.0911743321
4.69447 0.0991423267
EOD
$d3 << EOD
1.71163 0.131895499
1.78888 0.10912697
2.08589 0.0619345699
2.74608 0.0381718862
3.07158 0.0333727817
4.67805 0.0202708445
9.34364 0.00940802672
EOD
$d4 << EOD
1.67669 0.18389994
1.8372 0.137504239
2.20634 0.0581837434
2.97989 0.0389935079
3.31098 0.0263387288
5.17765 0.0151031223
10.7578 0.00737176612
EOD
$d5 << EOD
1.77379 0.129151376
1.93761 0.0939099121
2.23915 0.0955163124
2.82482 0.0854315137
3.15462 0.102575162
4.76636 0.104406437
9.46899 0.112496589
EOD
plot $d0 using 1:2 with linespoints title "Baumgarte float", \
     $d1 using 1:2 with linespoints title "SplitImpulse float", \
     $d2 using 1:2 with linespoints title "SoftStep float", \
     $d3 using 1:2 with linespoints dashtype 2 title "Baumgarte double", \
     $d4 using 1:2 with linespoints dashtype 2 title "SplitImpulse double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SoftStep double"
