// The hand-built families tables shared by the report's families tests: three classes, 4 trials
// each: sedan 3 right + 1 answered suv; suv 2 right + 1 sedan + 1 none; tank 4 right. 9 of 12
// classes right (the verify matrix of the methods tables).
#pragma once

namespace canopy::test {

inline const char* const kFamilyConfusion =
    "true_class,sedan,suv,tank,none\n"
    "sedan,3,1,0,0\n"
    "suv,1,2,0,1\n"
    "tank,0,0,4,0\n";
inline const char* const kFamilyAccuracy =
    "cover,noise,trials,class_right,class_accuracy,accepted,accepted_right,nearest_right,nearest_accuracy,"
    "failed\n"
    "light,0,6,5,0.8333,5,4,3,0.5000,0\n"
    "dense,32,6,4,0.6667,3,3,1,0.1667,1\n"
    "all,all,12,9,0.7500,8,7,4,0.3333,1\n";

}  // namespace canopy::test
