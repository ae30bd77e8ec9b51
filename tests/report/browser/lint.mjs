// ESLint over the page and its tests with zero warnings allowed; fails with the set-up hint when
// the npm packages are not installed. Run from the repo root: node tests/report/browser/lint.mjs
import { existsSync } from 'node:fs';
import { spawnSync } from 'node:child_process';
import { repoRoot } from './fixture.mjs';

const eslint = `${repoRoot}/node_modules/eslint/bin/eslint.js`;
if (!existsSync(eslint)) {
  console.error('lint: node_modules/eslint is missing: run scripts/setup.sh --test (it installs the npm packages)');
  process.exit(1);
}
const r = spawnSync(process.execPath, [eslint, '--max-warnings', '0', 'src/report/web', 'tests/report/browser', 'eslint.config.mjs'],
  { cwd: repoRoot, stdio: 'inherit' });
if (r.status === 0) console.log('lint: src/report/web and tests/report/browser pass ESLint with no warning');
process.exit(r.status === null ? 1 : r.status);
