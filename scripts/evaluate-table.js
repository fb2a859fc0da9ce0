// Writes the markdown table of scripts/evaluate-table.sh into docs/EVALUATION.md.
// Usage: node scripts/evaluate-table.js DIR docs/EVALUATION.md  (DIR holds <mesh>.json and `order`)
const fs = require('fs');
const path = require('path');
const [dir, document] = process.argv.slice(2);
const names = fs.readFileSync(path.join(dir, 'order'), 'utf8').split('\n').filter(Boolean);
const modes = ['turntable', 'paper', 'feature-orbit'];
const percent = (x) => (100 * x).toFixed(2) + ' %';
const lines = [
  '| mesh | path | feature coverage | surface coverage | feature frames min / median | camera speed (rad/frame) | view speed (rad/frame) | view acceleration (rad/frame²) | frames out |',
  '|---|---|---:|---:|---:|---:|---:|---:|---:|',
];
for (const name of names) {
  const doc = JSON.parse(fs.readFileSync(path.join(dir, name + '.json'), 'utf8')).modes;
  const best = Math.max(...modes.map((m) => doc[m].feature_coverage));
  for (const m of modes) {
    const e = doc[m];
    const features = e.feature_coverage === best ? '**' + percent(e.feature_coverage) + '**' : percent(e.feature_coverage);
    lines.push(`| ${m === modes[0] ? name : ''} | ${m} | ${features} | ${percent(e.surface_coverage)} | ` +
               `${e.feature_min_frames} / ${e.feature_median_frames} | ${e.camera_max_angular_speed.toFixed(4)} | ` +
               `${e.view_max_angular_speed.toFixed(4)} | ${e.view_max_angular_acceleration.toFixed(4)} | ${e.frames_out_of_frame} |`);
  }
}
// Second table: feature coverage under every feature definition (evaluate's "definitions"), the
// objective the feature orbit maximizes, and the best mode per definition in bold.
const first = JSON.parse(fs.readFileSync(path.join(dir, names[0] + '.json'), 'utf8')).modes[modes[0]];
const keys = Object.keys(first.definitions || {});
if (keys.length) {
  lines.push('', '| mesh | path | ' + keys.map((k) => 'features, ' + k).join(' | ') + ' | objective | best frame |',
             '|---|---|' + keys.map(() => '---:|').join('') + '---:|---:|');
  for (const name of names) {
    const doc = JSON.parse(fs.readFileSync(path.join(dir, name + '.json'), 'utf8')).modes;
    for (const m of modes) {
      const e = doc[m];
      const cells = keys.map((k) => {
        const best = Math.max(...modes.map((n) => doc[n].definitions[k].feature_coverage));
        const v = e.definitions[k].feature_coverage;
        return v === best ? '**' + percent(v) + '**' : percent(v);
      });
      const scores = e.frame_scores;
      const bestFrame = scores.indexOf(Math.max(...scores));
      lines.push(`| ${m === modes[0] ? name : ''} | ${m} | ${cells.join(' | ')} | ${e.objective.toFixed(3)} | ${bestFrame} |`);
    }
  }
}
const begin = '<!-- evaluate-table:begin -->', end = '<!-- evaluate-table:end -->';
const text = fs.readFileSync(document, 'utf8');
const a = text.indexOf(begin), b = text.indexOf(end);
if (a < 0 || b < a) {
  console.error(document + ': the ' + begin + ' and ' + end + ' markers are missing');
  process.exit(1);
}
fs.writeFileSync(document, text.slice(0, a + begin.length) + '\n' + lines.join('\n') + '\n' + text.slice(b));
