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
1.56556 0.145856865
1.62472 0.1108183
1.77814 0.0593302225
2.05419 0.0359545378
2.16126 0.0267508195
2.65871 0.0198719119
4.77501 0.00718087932
EOD
$d1 << EOD
1.44495 0.178714659
1.53036 0.124319239
1.73863 0.0560375987
2.11068 0.0370246868
2.64248 0.0402338725
4.48756 0.0162566953
8.45451 0.0316833496
EOD
$d2 << EOD
1.44075 0.134510017
1.51746 0.0965361185
1.89808 0.091940084
2.29103 0.0926571948
2.39095 0.0936472196
2.65243 0.0911743321
4.79083 0.0991423267
EOD
$d3 << EOD
2.23697 0.131895499
2.32963 0.10912697
2.67187 0.0619345699
3.36631 0.0381718862
3.6465 0.0333727817
5.44945 0.0202708445
10.0541 0.00940802672
EOD
$d4 << EOD
1.78533 0.18389994
2.12413 0.137504239
2.43644 0.0581837434
3.14842 0.0389935079
3.78725 0.0263387288
5.45322 0.0151031223
12.1576 0.00737176612
EOD
$d5 << EOD
2.46201 0.129151376
2.29061 0.0939099121
2.44553 0.0955163124
3.00073 0.0854315137
3.33573 0.102575162
5.56209 0.104406437
10.6451 0.112496589
EOD
plot $d0 using 1:2 with linespoints title "Baumgarte float", \
     $d1 using 1:2 with linespoints title "SplitImpulse float", \
     $d2 using 1:2 with linespoints title "SoftStep float", \
     $d3 using 1:2 with linespoints dashtype 2 title "Baumgarte double", \
     $d4 using 1:2 with linespoints dashtype 2 title "SplitImpulse double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SoftStep double"
