set terminal pngcairo size 960,600 noenhanced font 'sans,10'
set output 'projectile_error_vs_cost.png'
set title 'Projectile: position error after 10 s vs cost (dt 1/30 .. 1/1000)'
set xlabel 'ms of World::step per simulated second'
set ylabel '|x - x_exact| after 10 s, m'
set grid
set key outside right top
set logscale x
set format x '%g'
set logscale y
set format y '%.0e'
$d0 << EOD
0.0177683 1.63495463
0.0353717 0.816747918
0.0703449 0.409827042
0.141409 0.204265009
0.283343 0.0910531549
0.590101 0.0284447448
EOD
$d1 << EOD
0.0163073 1.6350344
0.0326486 0.818231492
0.0649434 0.407648511
0.130769 0.204497358
0.262068 0.113432617
0.548244 0.0698846271
EOD
$d2 << EOD
0.0165477 0.000170362635
0.0331037 0.000923291991
0.0656085 0.00130589188
0.132088 0.00142685633
0.265902 0.0115450939
0.554068 0.021049151
EOD
$d3 << EOD
0.0173563 0.000174110469
0.0345317 0.000758438897
0.0688225 0.00133180323
0.137599 0.00142901313
0.274864 0.0115450939
0.58281 0.0210793683
EOD
$d4 << EOD
0.0181099 1.635
0.0363223 0.8175
0.0720757 0.40875
0.145889 0.204375
0.293541 0.1021875
0.61434 0.04905
EOD
$d5 << EOD
0.0166419 1.635
0.0331806 0.8175
0.0659544 0.40875
0.132909 0.204375
0.26725 0.1021875
0.550476 0.04905
EOD
$d6 << EOD
0.0165166 4.43961294e-13
0.0330572 1.12004616e-12
0.0659833 1.98265616e-12
0.132135 3.36677313e-12
0.266313 5.82416238e-12
0.563194 4.4682708e-11
EOD
$d7 << EOD
0.0170495 4.43961294e-13
0.0342843 1.12004616e-12
0.0696508 1.98265616e-12
0.137936 3.36677313e-12
0.278264 5.82416238e-12
0.580827 4.4682708e-11
EOD
plot $d0 using 1:2 with linespoints title "ExplicitEuler float", \
     $d1 using 1:2 with linespoints title "SemiImplicitEuler float", \
     $d2 using 1:2 with linespoints title "ExactBallistic float", \
     $d3 using 1:2 with linespoints title "Rk4 float", \
     $d4 using 1:2 with linespoints dashtype 2 title "ExplicitEuler double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SemiImplicitEuler double", \
     $d6 using 1:2 with linespoints dashtype 2 title "ExactBallistic double", \
     $d7 using 1:2 with linespoints dashtype 2 title "Rk4 double"
