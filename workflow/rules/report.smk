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


for _ch in CHAPTERS:

    rule:
        name:
            f"report_figures_{_ch}"
        message:
            f"Rendering the figures of {_ch}"
        input:
            CHAPTER_TARGETS[_ch],
        output:
            manifest=f"reports/{PROFILE}/figures/{_ch}/manifest.json",
            pngs=[
                report(
                    figure_path(_ch, fig),
                    caption=f"../report/{_ch}/{fig}.rst",
                    category=CHAPTER_TITLES[_ch],
                )
                for fig in FIGURES[_ch]
            ],
        params:
            ch=_ch,
            code=REPORT_CODE,
        log:
            f"logs/{PROFILE}/report/figures_{_ch}.log",
        benchmark:
            bench_path("report", f"figures_{_ch}")
        threads: 1
        resources:
            **res("report", f"figures_{_ch}", mem_mb=2000, runtime=10),
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
