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
0.0225035 1.63495463
0.0484325 0.816747918
0.0948284 0.409827042
0.191899 0.204265009
0.382257 0.0910531549
0.793923 0.0284447448
EOD
$d1 << EOD
0.0210549 1.6350344
0.0454569 0.818231492
0.0881161 0.407648511
0.179276 0.204497358
0.360376 0.113432617
0.743754 0.0698846271
EOD
$d2 << EOD
0.0212308 0.000170362635
0.0459378 0.000923291991
0.122238 0.00130589188
0.179139 0.00142685633
0.356087 0.0115450939
0.747212 0.021049151
EOD
$d3 << EOD
0.0222258 0.000174110469
0.0478957 0.000758438897
0.0931282 0.00133180323
0.185543 0.00142901313
0.374572 0.0115450939
0.782237 0.0210793683
EOD
$d4 << EOD
0.022216 1.635
0.0476367 0.8175
0.0920086 0.40875
0.188038 0.204375
0.373681 0.1021875
0.778906 0.04905
EOD
$d5 << EOD
0.0207222 1.635
0.0446265 0.8175
0.0861989 0.40875
0.172455 0.204375
0.346035 0.1021875
0.722776 0.04905
EOD
$d6 << EOD
0.0208079 4.43961294e-13
0.0448865 1.12004616e-12
0.0870213 1.98265616e-12
0.173115 3.36677313e-12
0.349048 5.82416238e-12
0.72561 4.4682708e-11
EOD
$d7 << EOD
0.021257 4.43961294e-13
0.0457409 1.12004616e-12
0.0883971 1.98265616e-12
0.17696 3.36677313e-12
0.354912 5.82416238e-12
0.741024 4.4682708e-11
EOD
plot $d0 using 1:2 with linespoints title "ExplicitEuler float", \
     $d1 using 1:2 with linespoints title "SemiImplicitEuler float", \
     $d2 using 1:2 with linespoints title "ExactBallistic float", \
     $d3 using 1:2 with linespoints title "Rk4 float", \
     $d4 using 1:2 with linespoints dashtype 2 title "ExplicitEuler double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SemiImplicitEuler double", \
     $d6 using 1:2 with linespoints dashtype 2 title "ExactBallistic double", \
     $d7 using 1:2 with linespoints dashtype 2 title "Rk4 double"
