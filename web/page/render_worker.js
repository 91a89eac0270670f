// The worker that holds svetlo's WebAssembly module (docs/web.md): a render blocks it, not
// the page. In a cross-origin isolated page the module has threads (svetlo.js, its threads
// the module's own workers); elsewhere it is the single-threaded one (svetlo-st.js). Messages
// in: {id, scene, isText, options} or {id, files: [{name, bytes}]}; out: {ready} once, then
// {id, width, height, seconds, pixels}, {id, names} or {id, error}.
const script = self.crossOriginIsolated ? 'svetlo.js' : 'svetlo-st.js';
importScripts(script);

createSvetlo({
    // The module's files beside this script, whatever the page's own address.
    locateFile: (name) => new URL(name, self.location.href).href,
    // What the module's threads load (a modularized module inside a worker cannot tell).
    mainScriptUrlOrBlob: new URL(script, self.location.href).href,
    print: (text) => console.log(text),
    printErr: (text) => console.warn(text),
}).then((module) => {
    module.FS.chdir('/scenes');
    const scenes = module.FS.readdir('/scenes').filter((name) => name.endsWith('.json')).sort();
    self.postMessage({ready: true, scenes, engines: JSON.parse(module.engines()),
                      cores: self.crossOriginIsolated ? navigator.hardwareConcurrency || 1 : 1});
    // The visitor's files, under /scenes/visitor: each under its own name, without folders
    // (a name that would leave the folder, or is empty, is refused with the one-line error).
    const addFiles = (id, files) => {
        const folder = '/scenes/visitor';
        if (!module.FS.analyzePath(folder).exists) module.FS.mkdir(folder);
        const names = [];
        for (const f of files) {
            const name = f.name.split(/[\\/]/).pop();
            if (!name || name === '.' || name === '..') {
                self.postMessage({id, error: `svetlo: error: ${f.name}: not a file's name`});
                return;
            }
            module.FS.writeFile(folder + '/' + name, new Uint8Array(f.bytes));
            names.push(name);
        }
        self.postMessage({id, names});
    };
    self.onmessage = (event) => {
        if (event.data.files !== undefined) {
            addFiles(event.data.id, event.data.files);
            return;
        }
        const {id, scene, isText, options} = event.data;
        let out;
        try {
            out = module.render(scene, isText, JSON.stringify(options || {}));
        } catch (error) {  // the module itself failed (out of memory, an abort): say so
            self.postMessage({id, error: 'svetlo: the render failed: ' + error});
            return;
        }
        if (out.error !== undefined) {
            self.postMessage({id, error: out.error});
            return;
        }
        self.postMessage({id, width: out.width, height: out.height, seconds: out.seconds,
                          pixels: out.pixels}, [out.pixels.buffer]);
    };
}, (error) => self.postMessage({failed: String(error)}));
