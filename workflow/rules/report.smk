# Claims, figures and the HTML report. Figures are their own rules (one per chapter),
# separate from the simulations, so restyling never reruns an experiment.
import glob

ALL_RESULTS = [f for ch in CHAPTERS for f in CHAPTER_TARGETS[ch]]
# The perturbed and native twin runs made so far (`--config perturb=...`, `isa=native`,
# common.smk): the claims are decided on them too, and decided again when one is added or
# rerun.
TWIN_RUNS = sorted(glob.glob(f"results/{PROFILE}-perturbed/*/*.nc")) + sorted(
    glob.glob(f"results/{PROFILE}-native/*/*.nc")
)
REPORT_CODE = code_version(*CORE_CODE, "claims", "paper", "report")
CHAPTER_TITLES = {
    "ch2": "Chapter 2",
    "ch3": "Chapter 3",
    "ch4": "Chapter 4",
    "ch5": "Chapter 5",
    "ch6": "Chapter 6",
    "ch7": "Chapter 7",
    "coopt": "§8.2 co-optimisation",
}


rule claims:
    message:
        "Deciding every claim of the thesis from the {PROFILE} results"
    input:
        ALL_RESULTS,
        TWIN_RUNS,
        # the Oncilla's validation (workflow/rules/model.smk): claims on it are flagged
        MODEL_TARGETS,
    output:
        json=f"results/{PROFILE}/claims.json",
        # the decision rules' power table, written beside claims.json (thesis.cli)
        power=f"results/{PROFILE}/claims_power.json",
    params:
        code=REPORT_CODE,
    log:
        f"logs/{PROFILE}/claims.log",
    benchmark:
        bench_path("report", "claims")
    threads: 1
    resources:
        **res("report", "claims", mem_mb=2000, runtime=10),
    shell:
        "{THESIS} check --profile {PROFILE} --output {output.json} > {log} 2>&1"


def figure_outputs(ch):
    """The outputs of report_figures_<ch>: the manifest and the chapter's figures (PNG),
    each figure declared for ``snakemake --report`` with its caption file."""
    return dict(
        manifest=f"reports/{PROFILE}/figures/{ch}/manifest.json",
        pngs=[report(figure_path(ch, fig), caption=f"../report/{ch}/{fig}.rst",
                     category=CHAPTER_TITLES[ch]) for fig in FIGURES[ch]],
    )


rule report_figures_ch2:
    message:
        "Rendering the figures of ch2"
    input:
        CHAPTER_TARGETS["ch2"],
    output:
        **figure_outputs("ch2"),
    params:
        ch="ch2",
        code=REPORT_CODE,
    log:
        f"logs/{PROFILE}/report/figures_ch2.log",
    benchmark:
        bench_path("report", "figures_ch2")
    threads: 1
    resources:
        **res("report", "figures_ch2", mem_mb=2000, runtime=10),
    shell:
        "{THESIS} report --profile {PROFILE} --figures {params.ch} > {log} 2>&1"


rule report_figures_ch3:
    message:
        "Rendering the figures of ch3"
    input:
        CHAPTER_TARGETS["ch3"],
    output:
        **figure_outputs("ch3"),
    params:
        ch="ch3",
        code=REPORT_CODE,
    log:
        f"logs/{PROFILE}/report/figures_ch3.log",
    benchmark:
        bench_path("report", "figures_ch3")
    threads: 1
    resources:
        **res("report", "figures_ch3", mem_mb=2000, runtime=10),
    shell:
        "{THESIS} report --profile {PROFILE} --figures {params.ch} > {log} 2>&1"


rule report_figures_ch4:
    message:
        "Rendering the figures of ch4"
    input:
        CHAPTER_TARGETS["ch4"],
    output:
        **figure_outputs("ch4"),
    params:
        ch="ch4",
        code=REPORT_CODE,
    log:
        f"logs/{PROFILE}/report/figures_ch4.log",
    benchmark:
        bench_path("report", "figures_ch4")
    threads: 1
    resources:
        **res("report", "figures_ch4", mem_mb=2000, runtime=10),
    shell:
        "{THESIS} report --profile {PROFILE} --figures {params.ch} > {log} 2>&1"


rule report_figures_ch5:
    message:
        "Rendering the figures of ch5"
    input:
        CHAPTER_TARGETS["ch5"],
    output:
        **figure_outputs("ch5"),
    params:
        ch="ch5",
        code=REPORT_CODE,
    log:
        f"logs/{PROFILE}/report/figures_ch5.log",
    benchmark:
        bench_path("report", "figures_ch5")
    threads: 1
    resources:
        **res("report", "figures_ch5", mem_mb=2000, runtime=10),
    shell:
        "{THESIS} report --profile {PROFILE} --figures {params.ch} > {log} 2>&1"


rule report_figures_ch6:
    message:
        "Rendering the figures of ch6"
    input:
        CHAPTER_TARGETS["ch6"],
    output:
        **figure_outputs("ch6"),
    params:
        ch="ch6",
        code=REPORT_CODE,
    log:
        f"logs/{PROFILE}/report/figures_ch6.log",
    benchmark:
        bench_path("report", "figures_ch6")
    threads: 1
    resources:
        **res("report", "figures_ch6", mem_mb=2000, runtime=10),
    shell:
        "{THESIS} report --profile {PROFILE} --figures {params.ch} > {log} 2>&1"


rule report_figures_ch7:
    message:
        "Rendering the figures of ch7"
    input:
        CHAPTER_TARGETS["ch7"],
    output:
        **figure_outputs("ch7"),
    params:
        ch="ch7",
        code=REPORT_CODE,
    log:
        f"logs/{PROFILE}/report/figures_ch7.log",
    benchmark:
        bench_path("report", "figures_ch7")
    threads: 1
    resources:
        **res("report", "figures_ch7", mem_mb=2000, runtime=10),
    shell:
        "{THESIS} report --profile {PROFILE} --figures {params.ch} > {log} 2>&1"


rule report_figures_coopt:
    message:
        "Rendering the figures of coopt"
    input:
        CHAPTER_TARGETS["coopt"],
    output:
        **figure_outputs("coopt"),
    params:
        ch="coopt",
        code=REPORT_CODE,
    log:
        f"logs/{PROFILE}/report/figures_coopt.log",
    benchmark:
        bench_path("report", "figures_coopt")
    threads: 1
    resources:
        **res("report", "figures_coopt", mem_mb=2000, runtime=10),
    shell:
        "{THESIS} report --profile {PROFILE} --figures {params.ch} > {log} 2>&1"


rule report:
    message:
        "Rendering reports/{PROFILE}/index.html"
    input:
        claims=rules.claims.output.json,
        power=rules.claims.output.power,
        figures=[f"reports/{PROFILE}/figures/{ch}/manifest.json" for ch in CHAPTERS],
    output:
        html=f"reports/{PROFILE}/index.html",
        summary=f"reports/{PROFILE}/summary.md",
        measurements=f"reports/{PROFILE}/measurements.md",
        tables=[
            report(
                f"reports/{PROFILE}/tables/{ch}_{table}.html",
                caption=f"../report/{ch}/{table}.rst",
                category=CHAPTER_TITLES[ch],
            )
            for ch in CHAPTERS
            for table in TABLES[ch]
        ],
        claims=report(
            f"reports/{PROFILE}/tables/claims.html",
            caption="../report/claims.rst",
            category="Claims",
        ),
    params:
        code=REPORT_CODE,
    log:
        f"logs/{PROFILE}/report/index.log",
    benchmark:
        bench_path("report", "index")
    threads: 1
    resources:
        **res("report", "index", mem_mb=2000, runtime=10),
    shell:
        "{THESIS} report --profile {PROFILE} > {log} 2>&1"
