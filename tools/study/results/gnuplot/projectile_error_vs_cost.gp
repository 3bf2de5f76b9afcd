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
0.0227307 1.63495463
0.0468181 0.816747918
0.0956767 0.409827042
0.192921 0.204265009
0.386636 0.0910531549
0.797147 0.0284447448
EOD
$d1 << EOD
0.0212721 1.6350344
0.044462 0.818231492
0.0888314 0.407648511
0.181259 0.204497358
0.359613 0.113432617
0.749255 0.0698846271
EOD
$d2 << EOD
0.0214458 0.000170362635
0.0464017 0.000923291991
0.0893236 0.00130589188
0.181436 0.00142685633
0.360223 0.0115450939
0.749684 0.021049151
EOD
$d3 << EOD
0.0220914 0.000174110469
0.0477695 0.000758438897
0.0917004 0.00133180323
0.186302 0.00142901313
0.371659 0.0115450939
0.787491 0.0210793683
EOD
$d4 << EOD
0.0227693 1.635
0.0488863 0.8175
0.0944848 0.40875
0.189688 0.204375
0.382309 0.1021875
0.795975 0.04905
EOD
$d5 << EOD
0.021131 1.635
0.0433842 0.8175
0.0879669 0.40875
0.182631 0.204375
0.35583 0.1021875
0.740725 0.04905
EOD
$d6 << EOD
0.0213096 4.43961294e-13
0.0461328 1.12004616e-12
0.0889682 1.98265616e-12
0.183083 3.36677313e-12
0.3672 5.82416238e-12
0.748968 4.4682708e-11
EOD
$d7 << EOD
0.0218056 4.43961294e-13
0.046859 1.12004616e-12
0.0904805 1.98265616e-12
0.182341 3.36677313e-12
0.365268 5.82416238e-12
0.76637 4.4682708e-11
EOD
plot $d0 using 1:2 with linespoints title "ExplicitEuler float", \
     $d1 using 1:2 with linespoints title "SemiImplicitEuler float", \
     $d2 using 1:2 with linespoints title "ExactBallistic float", \
     $d3 using 1:2 with linespoints title "Rk4 float", \
     $d4 using 1:2 with linespoints dashtype 2 title "ExplicitEuler double", \
     $d5 using 1:2 with linespoints dashtype 2 title "SemiImplicitEuler double", \
     $d6 using 1:2 with linespoints dashtype 2 title "ExactBallistic double", \
     $d7 using 1:2 with linespoints dashtype 2 title "Rk4 double"
