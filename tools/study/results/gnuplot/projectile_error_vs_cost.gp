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
0.0220649 1.63495463
0.0455783 0.816747918
0.0891153 0.409827042
0.187982 0.204265009
0.378568 0.0910531549
0.816215 0.0284447448
EOD
$d1 << EOD
0.0193115 1.6350344
0.0419602 0.818231492
0.0833258 0.407648511
0.169652 0.204497358
0.359215 0.113432617
0.771379 0.0698846271
EOD
$d2 << EOD
0.0192609 0.000170362635
0.0430354 0.000923291991
0.0805508 0.00130589188
0.174279 0.00142685633
0.355218 0.0115450939
0.858432 0.021049151
EOD
$d3 << EOD
0.0288614 0.000174110469
0.0443807 0.000758438897
0.0842886 0.00133180323
0.177724 0.00142901313
0.37777 0.0115450939
0.964241 0.0210793683
EOD
$d4 << EOD
0.0203392 1.635
0.0441705 0.8175
0.0853354 0.40875
0.173491 0.204375
0.349703 0.1021875
0.931741 0.04905
EOD
$d5 << EOD
0.023947 1.635
0.052242 0.8175
0.101315 0.40875
0.205469 0.204375
0.429109 0.1021875
0.903475 0.04905
EOD
$d6 << EOD
0.0250468 4.43961294e-13
0.054443 1.12004616e-12
0.105677 1.98265616e-12
0.214893 3.36677313e-12
0.426587 5.82416238e-12
0.897798 4.4682708e-11
EOD
$d7 << EOD
0.0259383 4.43961294e-13
0.0563176 1.12004616e-12
0.106882 1.98265616e-12
0.21777 3.36677313e-12
0.443638 5.82416238e-12
0.911066 4.4682708e-11
EOD
plot $d0 using 1:2 with linespoints title "ExplicitEuler float", \
     $d1 using 1:2 with linespoints title "SemiImplicitEuler float", \
     $d2 using 1:2 with linespoints title "ExactBallistic float", \
     $d3 using 1:2 with linespoints title "Rk4 float", \
     $d4 using 1:2 with linespoints dashtype 2 title "ExplicitEuler double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SemiImplicitEuler double", \
     $d6 using 1:2 with linespoints dashtype 2 title "ExactBallistic double", \
     $d7 using 1:2 with linespoints dashtype 2 title "Rk4 double"
