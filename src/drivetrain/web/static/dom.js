// DOM helper shared by the page's modules: build an element with attributes and children.
// Text goes in through textContent only, never as HTML.

export function el(tag, attrs = {}, ...children) {
  const node = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (v === undefined || v === null || v === false) continue;
    if (k === "text") node.textContent = v;
    else node.setAttribute(k, v === true ? "" : v);
  }
  for (const c of children) if (c !== null && c !== undefined) node.append(c);
  return node;
}

// A destructive button asks twice: the first click arms it for 4 s ("Really delete?"), the second
// within that time returns true. ``holder[key]`` keeps the timer of the armed button.
export function confirmedTwice(button, holder, key = "deleteArmed", label = "Delete") {
  if (!holder[key]) {
    button.textContent = "Really delete?";
    holder[key] = setTimeout(() => {
      button.textContent = label;
      holder[key] = null;
    }, 4000);
    return false;
  }
  clearTimeout(holder[key]);
  holder[key] = null;
  button.textContent = label;
  return true;
}
