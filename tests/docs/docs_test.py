#!/usr/bin/env python3
"""The repository stands alone: every citation in code and documents points at a file of the repository or at
a primary source, and every relative Markdown link of the README and docs/ resolves (the file, and the heading
for a #fragment, by GitHub's slug rules). Usage: docs_test.py REPOSITORY_ROOT"""
import pathlib
import re
import sys

root = pathlib.Path(sys.argv[1]).resolve()
failures = []

# 1. No citation of design notes that are not in the repository.
outside = re.compile(r'(?<![\w/.\[])DESIGN §|\bSTYLE "For iblx"|sampling_sota|\.\./shared/')
for path in sorted(root.rglob('*')):
    rel = path.relative_to(root)
    if rel.parts[0] in ('.git', 'third_party') or rel.parts[0].startswith('build') or not path.is_file():
        continue
    if path.suffix not in ('.cpp', '.h', '.glsl', '.comp', '.md', '.sh', '.toml', '.txt', '.py', '.sbatch'):
        continue
    if rel == pathlib.Path('tests/docs/docs_test.py'):
        continue
    for number, line in enumerate(path.read_text(errors='replace').splitlines(), 1):
        if outside.search(line):
            failures.append(f'{rel}:{number}: cites a note outside the repository: {line.strip()[:100]}')


def slug(heading):
    """GitHub's anchor of a Markdown heading."""
    text = re.sub(r'`|\*\*|\*|_(?=\w)|\[|\]\([^)]*\)', '', heading.strip().lower())
    text = re.sub(r'[^\w\- ]', '', text)
    return text.replace(' ', '-')


def anchors(path):
    found = set()
    counts = {}
    for line in path.read_text().splitlines():
        m = re.match(r'#{1,6} (.*)', line)
        if m:
            base = slug(m.group(1))
            n = counts.get(base, 0)
            found.add(base if n == 0 else f'{base}-{n}')
            counts[base] = n + 1
    return found


# 2. Relative links of the README and docs/*.md.
link = re.compile(r'\[[^\]]*\]\(([^)\s]+)\)')
for doc in [root / 'README.md', *sorted((root / 'docs').rglob('*.md'))]:
    in_code = False
    for number, line in enumerate(doc.read_text().splitlines(), 1):
        if line.startswith('```'):
            in_code = not in_code
        if in_code:
            continue
        for target in link.findall(line):
            if re.match(r'[a-z]+:', target):
                continue
            file, _, fragment = target.partition('#')
            dest = (doc.parent / file).resolve() if file else doc
            where = f'{doc.relative_to(root)}:{number}: {target}'
            if not dest.exists():
                failures.append(f'{where}: no such file')
            elif fragment and dest.suffix == '.md' and fragment not in anchors(dest):
                failures.append(f'{where}: no heading with this anchor in {dest.relative_to(root)}')

for f in failures:
    print('FAIL:', f)
print(f'docs: {len(failures)} problems')
sys.exit(1 if failures else 0)
