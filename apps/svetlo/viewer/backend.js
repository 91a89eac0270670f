// How the viewer's requests travel in svetlo serve's page (docs/viewer.md): to the server that
// sent the page, by the browser's own fetch. The web page has its own backend.js, which hands
// the same requests to svetlo's WebAssembly module (docs/web.md). The viewer (viewer.js) asks
// svetloViewer for:
//   fetch(target, init)   a Response to "/api/...", as fetch gives it (init.signal aborts it)
//   ready                 a promise settled when requests can be made (optional)
//   note                  a line the page shows under the image (optional)
//   addFiles(files)       the visitor's own files put in the scene folder (optional)
"use strict";
self.svetloViewer = { fetch: (target, init) => fetch(target, init) };
