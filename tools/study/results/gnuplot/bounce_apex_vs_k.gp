set terminal pngcairo size 960,600 noenhanced font 'sans,10'
set output 'bounce_apex_vs_k.png'
set title 'Bounce: apex height after bounce k (points) vs h*e^(2k) (lines), base setting, float'
set xlabel 'bounce k'
set ylabel 'apex height, m'
set grid
set key outside right top
set logscale y
set format y '%.0e'
set yrange [1e-3:20]
set xrange [0:21]
$d0 << EOD
1 2.46101249
2 0.558710273
3 0.119751117
4 0.0198041316
EOD
$d1 << EOD
1 2.5
2 0.625
3 0.15625
4 0.0390625
EOD
$d2 << EOD
1 7.97367999
2 6.12538704
3 4.80010502
4 3.66728301
5 2.77226465
6 2.12618526
7 1.63557553
8 1.22768909
9 0.927022907
10 0.685129895
11 0.467232312
12 0.337283924
13 0.224619464
14 0.137458682
15 0.0885165923
16 0.0531520112
EOD
$d3 << EOD
1 8.1
2 6.561
3 5.31441
4 4.3046721
5 3.4867844
6 2.82429536
7 2.28767925
8 1.85302019
9 1.50094635
10 1.21576655
11 0.984770902
12 0.797664431
13 0.646108189
14 0.523347633
15 0.423911583
16 0.343368382
17 0.278128389
18 0.225283995
19 0.182480036
20 0.147808829
EOD
$d4 << EOD
1 9.84404862
2 9.38625206
3 9.16143601
4 8.7199919
5 8.5033497
6 8.28944006
7 8.07825046
8 7.66405955
9 7.46103436
10 7.06319893
11 6.8683481
12 6.48686535
13 6.30018247
14 5.9350533
15 5.75654837
16 5.40776619
17 5.23743508
18 4.90500402
19 4.74285068
20 4.42676681
EOD
$d5 << EOD
1 10
2 10
3 10
4 10
5 10
6 10
7 10
8 10
9 10
10 10
11 10
12 10
13 10
14 10
15 10
16 10
17 10
18 10
19 10
20 10
EOD
plot $d0 using 1:2 with points pointsize 1.5 title "e=0.5 measured", \
     $d1 using 1:2 with lines title "e=0.5 expected", \
     $d2 using 1:2 with points pointsize 1.5 title "e=0.9 measured", \
     $d3 using 1:2 with lines title "e=0.9 expected", \
     $d4 using 1:2 with points pointsize 1.5 title "e=1 measured", \
     $d5 using 1:2 with lines title "e=1 expected"
