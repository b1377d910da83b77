// hard_warps_fpr: the false-failure rate of the catalogue of correct-but-hard
// warps over seeds, with its exact (Clopper-Pearson) 95% interval, measured
// as warpcheck_fpr measures the built-in warps (validate/trust/fpr.h). The wrong
// twins (known flaws) are left out.
//     hard_warps_fpr --runs 20 --first-seed 1 --alpha 0.01
#include <validate/api/external.h>
#include <validate/trust/fpr.h>

int main(int argc, char** argv) {
    return warpcheck::fpr_main(argc, argv,
                               {.name = "hard_warps_fpr",
                                .description = "Measures how often the correct-but-hard catalogue of issue 22 fails",
                                .register_cases = warpcheck_register,
                                .power_check = true});
}
