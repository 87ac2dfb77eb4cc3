// Folding panels, for small screens: each card's heading folds it (all but the first of the
// controls start folded below NARROW px), and the header's secondary controls fold behind a
// "More" button there.

/// The width (CSS px) below which the layout is a single column (app.css has the same).
export const NARROW = 900;

/// Makes every `.card` with an `h2` foldable by its heading.
export function setupFolding() {
  const narrow = window.matchMedia(`(max-width: ${NARROW - 0.02}px)`).matches;
  for (const card of document.querySelectorAll('.card')) {
    const h = card.querySelector(':scope > h2');
    if (!h) continue;
    const button = document.createElement('button');
    button.className = 'fold';
    button.type = 'button';
    button.append(...h.childNodes);
    h.replaceChildren(button);
    if (h.id) {
      // The heading's text is set by id (the material's name): it is the button's now.
      button.id = h.id;
      h.removeAttribute('id');
    }
    const set = (folded) => {
      card.classList.toggle('folded', folded);
      button.setAttribute('aria-expanded', String(!folded));
    };
    button.addEventListener('click', () => set(!card.classList.contains('folded')));
    const controls = card.closest('.panel.controls');
    set(narrow && !!controls && card !== controls.querySelector('.card'));
  }
  const more = document.getElementById('more');
  more.addEventListener('click', () => {
    const open = document.body.classList.toggle('more-open');
    more.setAttribute('aria-expanded', String(open));
  });
}
