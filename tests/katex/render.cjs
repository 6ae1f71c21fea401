// Typeset LaTeX formulas with KaTeX (throwOnError, strict): reads a JSON array of strings on
// stdin, writes a JSON array of {ok, error} on stdout. Used by tests/test_export_latex.py.
const katex = require("katex");
let input = "";
process.stdin.on("data", (chunk) => (input += chunk));
process.stdin.on("end", () => {
  const results = JSON.parse(input).map((tex) => {
    try {
      katex.renderToString(tex, { displayMode: true, throwOnError: true, strict: "error" });
      return { ok: true, error: null };
    } catch (e) {
      return { ok: false, error: String(e.message || e) };
    }
  });
  process.stdout.write(JSON.stringify(results));
});
