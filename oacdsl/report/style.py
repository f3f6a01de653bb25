"""The report page's stylesheet (inlined into the page: no network, no JavaScript)."""

CSS = """
:root { --ink:#1d232a; --muted:#5b6672; --line:#dde2e8; --soft:#f4f6f9; --accent:#2f5d8a;
        --ok:#1a7f37; --okbg:#e8f5ec; --bad:#c62828; --badbg:#fdecec; --warn:#a85d00; --warnbg:#fff4e0; }
* { box-sizing: border-box; }
html { -webkit-text-size-adjust: 100%; }
body { margin: 0; color: var(--ink); background: #fff;
       font: 15px/1.5 -apple-system, "Segoe UI", "Helvetica Neue", "DejaVu Sans", Arial, sans-serif; }
main { max-width: 1200px; margin: 0 auto; padding: 28px 32px 60px; }
h1 { font-size: 28px; line-height: 1.2; margin: 4px 0 6px; font-weight: 650; letter-spacing: -0.01em; }
h2 { font-size: 21px; margin: 44px 0 6px; padding-bottom: 6px; border-bottom: 2px solid var(--ink);
     font-weight: 650; }
h3 { font-size: 16px; margin: 22px 0 8px; font-weight: 650; }
p { margin: 6px 0 10px; }
.lead { color: var(--muted); margin: 0 0 14px; max-width: 60em; }
.kicker { text-transform: uppercase; letter-spacing: .08em; font-size: 12px; color: var(--accent);
          font-weight: 650; }
.sub { color: var(--muted); font-size: 14px; }
code, pre, .mono { font-family: "DejaVu Sans Mono", Menlo, Consolas, monospace; font-size: 13px; }
code { background: var(--soft); padding: 1px 4px; border-radius: 3px; }
pre { background: #f7f8fa; border: 1px solid var(--line); border-radius: 6px; padding: 12px 14px;
      overflow-x: auto; line-height: 1.45; margin: 8px 0; }
pre .kw { color: #8a2be2; font-weight: 600; } pre .cm { color: #6a737d; font-style: italic; }
pre .op { color: var(--accent); font-weight: 600; } pre .st { color: #22863a; }
nav.toc { margin: 18px 0 4px; font-size: 14px; }
nav.toc a { color: var(--accent); text-decoration: none; margin-right: 16px; white-space: nowrap; }
nav.toc a:hover { text-decoration: underline; }
.verdict { border-radius: 8px; padding: 14px 18px; margin: 16px 0; border-left: 6px solid; }
.verdict.ok { background: var(--okbg); border-color: var(--ok); }
.verdict.fail { background: var(--badbg); border-color: var(--bad); }
.verdict .big { font-size: 19px; font-weight: 650; }
.verdict.ok .big { color: var(--ok); } .verdict.fail .big { color: var(--bad); }
.verdict p { margin: 4px 0 0; }
.cards { display: flex; flex-wrap: wrap; gap: 10px; margin: 12px 0; }
.card { border: 1px solid var(--line); border-radius: 8px; padding: 8px 14px; flex: 1 1 0; min-width: 120px; }
.card .v { font-size: 20px; font-weight: 650; } .card .k { font-size: 12px; color: var(--muted); }
.card.ok .v { color: var(--ok); } .card.bad .v { color: var(--bad); }
table { border-collapse: collapse; width: 100%; margin: 8px 0 14px; font-size: 14px; }
th, td { border-bottom: 1px solid var(--line); padding: 6px 10px; text-align: left; vertical-align: top; }
th { background: var(--soft); font-weight: 600; font-size: 13px; color: #39424c;
     border-bottom: 1px solid #c9d0d8; }
td.num, th.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
table.kv { width: auto; } table.kv th { background: none; border: 0; padding-left: 0; color: var(--muted); }
table.fig4 td { padding: 10px; } table.fig4 td.kf { width: 215px; } table.fig4 td.graph { width: 290px; }
table.fig4 td.robot { width: 250px; } .kfn { font-size: 20px; font-weight: 700; line-height: 1.1; }
td.shot { width: 210px; } td.shot img.frame { width: 200px; }
td.shot.two { width: 416px; } td.shot .pair { display: flex; gap: 8px; }
table.align td.side { width: 44%; } table.align td.op { width: 8%; text-align: center; }
.chips { display: flex; flex-wrap: wrap; gap: 6px 8px; margin: 8px 0 12px; font-size: 13px; }
.chips span { background: var(--soft); border-radius: 4px; padding: 2px 8px; }
.chips b { color: var(--muted); font-weight: 600; margin-right: 6px; }
img { max-width: 100%; height: auto; display: block; }
img.graph { width: 270px; } img.frame { width: 240px; border-radius: 4px; border: 1px solid var(--line); }
img.snap { width: 200px; margin-top: 6px; }
img.wide { width: 100%; border: 1px solid var(--line); border-radius: 6px; }
figure { margin: 10px 0 18px; } figcaption { color: var(--muted); font-size: 13px; margin-top: 4px; }
.noimg { border: 1px dashed #c3cad2; border-radius: 4px; color: var(--muted); font-size: 12px;
         padding: 18px 10px; text-align: center; background: #fafbfc; }
.oacbox { background: #eef1f4; border-radius: 6px; padding: 8px 12px; }
.oacbox .call { font-weight: 650; }
.oacbox .cons { margin-top: 4px; font-size: 13px; }
.oacbox .cons b { display: inline-block; width: 52px; color: var(--muted); font-weight: 600; }
.runners { margin-top: 8px; font-size: 12.5px; color: var(--muted); }
.runners ol { margin: 2px 0 0 18px; padding: 0; }
.rel { font-family: "DejaVu Sans Mono", Menlo, Consolas, monospace; font-size: 12.5px; white-space: nowrap; }
.rels { font-size: 12.5px; color: #39424c; }
.badge { display: inline-block; border-radius: 10px; padding: 0 8px; font-size: 12px; font-weight: 600;
         line-height: 20px; white-space: nowrap; }
.badge.ok { background: var(--okbg); color: var(--ok); }
.badge.bad { background: var(--badbg); color: var(--bad); }
.badge.warn { background: var(--warnbg); color: var(--warn); }
.badge.mute { background: var(--soft); color: var(--muted); }
tr.bad td { background: var(--badbg); } tr.warn td { background: var(--warnbg); }
tr.op-missing td, tr.op-extra td { background: var(--badbg); }
tr.op-substitute td { background: var(--warnbg); }
.err { color: var(--bad); font-size: 13px; margin-top: 4px; }
.muted { color: var(--muted); } .small { font-size: 12.5px; }
.bar { background: var(--soft); height: 8px; border-radius: 4px; position: relative; min-width: 120px; }
.bar .fill { background: var(--accent); height: 8px; border-radius: 4px; position: absolute;
             left: 0; top: 0; }
.bar .fill.bad { background: var(--bad); }
.bar .ci { position: absolute; top: 0; height: 8px; background: rgba(47, 93, 138, .28); border-radius: 4px; }
.bar .pt { position: absolute; top: -3px; width: 3px; height: 14px; margin-left: -1px;
           background: var(--accent); border-radius: 1px; }
.cols { display: flex; gap: 24px; flex-wrap: wrap; } .cols > div { flex: 1 1 320px; }
footer { margin-top: 48px; padding-top: 10px; border-top: 1px solid var(--line); color: var(--muted);
         font-size: 12.5px; }
table.stages td:nth-child(1) { width: 3%; } table.stages td:nth-child(2) { width: 14%; }
table.stages td:nth-child(3) { width: 10%; }
table.stages td:nth-child(4) { width: 10%; } table.stages td:nth-child(5) { width: 26%; }
@media print { main { max-width: none; padding: 0; } h2 { break-after: avoid; } tr { break-inside: avoid; } }
"""
