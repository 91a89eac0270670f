// The worker that holds svetlo's WebAssembly module (docs/web.md): a render blocks it, not
// the page. In a cross-origin isolated page the module has threads (svetlo.js, its threads
// the module's own workers); elsewhere it is the single-threaded one (svetlo-st.js).
// Messages in: {id, scene, isText, options, wantsPasses}, {id, files: [{name, bytes}]}, or a
// viewer's request {id, api: TARGET} or {id, stream: TARGET} (/api/progressive); out:
// {ready, memory, cancelAt} once, then {id, pass} after each pass of a progressive engine,
// {id, chunk} with a stream's bytes, and {id, width, height, seconds, passes, cancelled,
// pixels}, {id, names}, {id, response: {status, type, headers, body}} or {id, error}. Where
// the module has threads its memory is shared with the page, which ends a render after its
// pass by setting the byte at cancelAt.
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
    // The viewer's requests, answered as svetlo serve answers them; cornell.json its first view.
    const viewer = new module.Viewer('/scenes/cornell.json');
    const cancelAt = module.cancelFlag();
    const shared = typeof SharedArrayBuffer !== 'undefined' &&
                   module.HEAP8.buffer instanceof SharedArrayBuffer;
    const scenes = module.FS.readdir('/scenes').filter((name) => name.endsWith('.json')).sort();
    // The engines as the viewer's /api/engines lists them (the job layer's registry).
    const engines = JSON.parse(new TextDecoder().decode(viewer.get('/api/engines', 0).body));
    self.postMessage({ready: true, scenes, engines,
                      cores: self.crossOriginIsolated ? navigator.hardwareConcurrency || 1 : 1,
                      memory: shared ? module.HEAP8.buffer : null, cancelAt});
    // The visitor's files, in /scenes beside the bundled scenes: each under its own name,
    // without folders (a name that would leave the folder, or is empty, is refused with the
    // one-line error).
    const addFiles = (id, files) => {
        const folder = '/scenes';
        const names = [];
        for (const f of files) {
            const name = f.name.split(/[\\/]/).pop();
            if (!name || name === '.' || name === '..') {
                self.postMessage({id, error: `${f.name}: addFiles: not a file's name`});
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
        if (event.data.api !== undefined || event.data.stream !== undefined) {
            const id = event.data.id;
            module.clearCancelFlag(cancelAt);
            let response;
            try {
                response = event.data.api !== undefined
                    ? viewer.get(event.data.api, cancelAt)
                    : viewer.stream(event.data.stream, cancelAt,
                                    (chunk) => self.postMessage({id, chunk}, [chunk.buffer]));
            } catch (error) {  // the module itself failed (out of memory, an abort)
                response = {status: 500, type: 'text/plain', headers: {},
                            body: new TextEncoder().encode('svetlo: the request failed: ' + error)};
            }
            self.postMessage({id, response}, [response.body.buffer]);
            return;
        }
        const {id, scene, isText, options, wantsPasses} = event.data;
        const onPass = (pass) => self.postMessage({id, pass}, [pass.pixels.buffer]);
        let out;
        try {
            module.clearCancelFlag(cancelAt);
            out = module.render(scene, isText, JSON.stringify(options || {}), cancelAt,
                                wantsPasses ? onPass : null);
        } catch (error) {  // the module itself failed (out of memory, an abort): say so
            self.postMessage({id, error: 'svetlo: the render failed: ' + error});
            return;
        }
        if (out.error !== undefined) {
            self.postMessage({id, error: out.error});
            return;
        }
        self.postMessage({id, width: out.width, height: out.height, seconds: out.seconds,
                          passes: out.passes, cancelled: out.cancelled, pixels: out.pixels},
                         [out.pixels.buffer]);
    };
}, (error) => self.postMessage({failed: String(error)}));
