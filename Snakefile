# The thesis reproduction pipeline: a table of contents.
#
#   snakemake --config profile=default            # everything, ends in reports/default/index.html
#   snakemake ch3 --config profile=smoke          # one chapter
#   snakemake results/smoke/ch7/ball.nc --config profile=smoke   # one table
#
# The profile (smoke | default | paper | gpu) selects config/<profile>.yaml; it is validated
# against config/schema.yaml before any job runs. Execution settings (cores, executor)
# live in profiles/default (loaded automatically) and profiles/slurm.
from snakemake.utils import min_version

min_version("9.0")

PROFILES = ["smoke", "default", "paper", "gpu"]
if config.get("profile", "default") not in PROFILES:
    raise ValueError(
        f"config key 'profile' = {config.get('profile')!r} is not allowed; "
        f"allowed values: {', '.join(PROFILES)}"
    )


configfile: f"config/{config.get('profile', 'default')}.yaml"


# common.smk validates the merged config against config/schema.yaml and fills its
# defaults (thesis.config.validate_config: errors name the key and the allowed values).
include: "workflow/rules/common.smk"


report: "workflow/report/workflow.rst"


include: "workflow/rules/ch2.smk"
include: "workflow/rules/ch3.smk"
include: "workflow/rules/ch4.smk"
include: "workflow/rules/ch5.smk"
include: "workflow/rules/ch6.smk"
include: "workflow/rules/ch7.smk"
include: "workflow/rules/coopt.smk"
include: "workflow/rules/model.smk"


# `--config perturb=1e-7` makes the perturbed twin runs of every chapter but ch6 (whose
# runs carry their own twins) into results/<profile>-perturbed/, `--config isa=native`
# the native twin runs of every chapter (the host's own code paths) into
# results/<profile>-native/; both leave the timings aside (a wall clock is no verdict's
# input). The claims and the report stay with the profile's own run, which reads the twins.
if not TWIN:

    include: "workflow/rules/report.smk"

TIMINGS = [result("ch2", "chirpz_scaling"), result("ch7", "table7_1")]


def chapter(ch):
    """A chapter's targets; a twin run's leave the timings out."""
    return [f for f in CHAPTER_TARGETS[ch] if not (TWIN and f in TIMINGS)]


rule all:
    default_target: True
    input:
        (
            rules.report.output.html
            if not TWIN
            else [
                f
                for ch in CHAPTERS
                if NATIVE or ch != "ch6"
                for f in chapter(ch)
            ]
        ),


rule ch2:
    input:
        chapter("ch2"),


rule ch3:
    input:
        chapter("ch3"),


rule ch4:
    input:
        chapter("ch4"),


rule ch5:
    input:
        chapter("ch5"),


rule ch6:
    input:
        chapter("ch6"),


rule ch7:
    input:
        chapter("ch7"),


rule coopt:
    input:
        chapter("coopt"),
