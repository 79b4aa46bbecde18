//! The PDBx/mmCIF reader: a streaming CIF tokenizer (the syntax of S. R. Hall, F. H. Allen,
//! I. D. Brown, "The Crystallographic Information File", Acta Cryst. A47 (1991) 655–685, as
//! CIF 1.1 specifies it) and three categories of the PDBx/mmCIF dictionary (wwPDB,
//! mmcif.wwpdb.org):
//!
//! - `_atom_site`: `Cartn_x`, `Cartn_y`, `Cartn_z` (Ångström, required), `type_symbol`
//!   (element), `label_atom_id` and `label_comp_id` (the element's fallback),
//!   `label_alt_id`, `label_asym_id` (the chain; `auth_asym_id` when absent) and
//!   `pdbx_PDB_model_num`; the first model and the first alternate location are kept, as
//!   for PDB. Each atom's fields: `label_atom_id`, `label_comp_id`, `auth_seq_id` (else
//!   `label_seq_id`), `pdbx_PDB_ins_code`, `B_iso_or_equiv`, `occupancy` and `group_PDB`.
//! - `_pdbx_struct_oper_list`: `id`, `matrix[i][j]`, `vector[i]`.
//! - `_pdbx_struct_assembly_gen`: `assembly_id`, `oper_expression` (`1`, `1,2,5`, `(1-60)`,
//!   and products such as `(1-60)(61-88)`, whose left factor applies last), `asym_id_list`.
//!
//! Values are read as they stream past, into reused buffers: no per-atom allocation. Only
//! the first data block is read. A loop whose values do not fill its last row is an error.

mod columns;
mod operators;
mod tokens;

use std::collections::HashMap;

use crate::assembly::Operator;
use crate::element::{element_from_bare_name, Element};
use crate::error::{quote, Error};
use crate::field::{finite, optional, parse_count};
use crate::fields::FieldsIn;
use crate::input::Lines;
use crate::molecule::{Builder, Molecule};
use crate::options::{Format, Limits};
use columns::{value, AtomColumn, AtomRow, Category};
use tokens::{is_null, tokens, Token};

/// The most operators an `oper_expression` may expand to.
const MAX_OPERATORS: usize = 1 << 16;

/// The loop (or the run of `_category.item value` pairs) being read.
struct Table {
    category: Category,
    /// Column names (items), for the small categories kept as text.
    items: Vec<Vec<u8>>,
    atom_columns: Vec<AtomColumn>,
    column: usize,
    /// The small categories' current row, as text.
    text_row: Vec<Vec<u8>>,
}

/// One `_pdbx_struct_assembly_gen` row.
struct AssemblyGen {
    line: u64,
    assembly: String,
    expression: String,
    chains: Vec<String>,
}

/// The reader's state between tokens.
struct Reader<'a> {
    file: &'a str,
    atoms: Builder<'a>,
    row: AtomRow,
    first_model: Option<Vec<u8>>,
    other_model_atoms: u64,
    first_alt: Option<Vec<u8>>,
    other_alt_atoms: u64,
    operators: HashMap<String, Operator>,
    operator_order: Vec<String>,
    generators: Vec<AssemblyGen>,
    /// Loop tags not yet followed by a value.
    loop_tags: Option<Vec<Vec<u8>>>,
    /// A `_category.item` outside a loop waiting for its value.
    pair_tag: Option<Vec<u8>>,
    table: Option<Table>,
    /// Whether the current table came from `loop_` (else from pairs).
    table_is_loop: bool,
    data_blocks: u32,
}

impl Reader<'_> {
    fn malformed(&self, line: u64, why: String) -> Error {
        Error::Malformed { file: self.file.to_owned(), line, why }
    }

    fn token(&mut self, token: Token<'_>, line: u64) -> Result<(), Error> {
        match token {
            Token::Data => {
                self.end_table(line)?;
                self.data_blocks += 1;
            }
            Token::Loop => {
                self.end_table(line)?;
                self.loop_tags = Some(Vec::new());
            }
            Token::Tag(tag) => {
                if let Some(tags) = &mut self.loop_tags {
                    tags.push(tag.to_vec());
                    return Ok(());
                }
                if self.pair_tag.is_some() {
                    return Err(self.malformed(line, format!("{} follows a tag that has no value", quote(tag))));
                }
                let (category, _) = Category::of(tag);
                let same_pairs = !self.table_is_loop && self.table.as_ref().is_some_and(|t| t.category == category);
                if !same_pairs {
                    self.end_table(line)?;
                }
                self.pair_tag = Some(tag.to_vec());
            }
            Token::Value(value) => {
                if let Some(tags) = self.loop_tags.take() {
                    if tags.is_empty() {
                        return Err(self.malformed(line, "loop_ without tags".to_owned()));
                    }
                    self.begin_table(&tags, true, line)?;
                    return self.value(value, line);
                }
                if let Some(tag) = self.pair_tag.take() {
                    if let Some(table) = &mut self.table {
                        let (_, item) = Category::of(&tag);
                        table.items.push(item.to_vec());
                        table.atom_columns.push(AtomColumn::of(item));
                        table.text_row.push(Vec::new());
                        table.column = table.items.len() - 1;
                    } else {
                        self.begin_table(&[tag], false, line)?;
                    }
                    return self.value(value, line);
                }
                if self.table.is_some() && self.table_is_loop {
                    return self.value(value, line);
                }
                return Err(self.malformed(line, format!("value {} without a tag", quote(value))));
            }
        }
        Ok(())
    }

    fn begin_table(&mut self, tags: &[Vec<u8>], is_loop: bool, line: u64) -> Result<(), Error> {
        let (category, _) = Category::of(tags.first().map(Vec::as_slice).unwrap_or_default());
        let items: Vec<Vec<u8>> = tags.iter().map(|t| Category::of(t).1.to_vec()).collect();
        let atom_columns: Vec<AtomColumn> = items.iter().map(|i| AtomColumn::of(i)).collect();
        if category == Category::AtomSite && is_loop {
            for required in [AtomColumn::X, AtomColumn::Y, AtomColumn::Z] {
                if !atom_columns.contains(&required) {
                    return Err(self.malformed(line, format!("_atom_site loop has no {}", required.field())));
                }
            }
        }
        let text_row = vec![Vec::new(); items.len()];
        self.table = Some(Table { category, items, atom_columns, column: 0, text_row });
        self.table_is_loop = is_loop;
        Ok(())
    }

    /// The next value of the current table.
    fn value(&mut self, value: &[u8], line: u64) -> Result<(), Error> {
        let Some(table) = &mut self.table else { return Ok(()) };
        let column = table.column;
        match table.category {
            Category::Other => {}
            Category::AtomSite => {
                let kind = table.atom_columns.get(column).copied().unwrap_or(AtomColumn::Skip);
                self.row.keep(kind, value).map_err(|why| Error::Field {
                    file: self.file.to_owned(),
                    line,
                    record: "_atom_site",
                    field: kind.field(),
                    value: quote(value),
                    why,
                })?;
            }
            Category::OperList | Category::AssemblyGen => {
                if let Some(cell) = table.text_row.get_mut(column) {
                    cell.clear();
                    cell.extend_from_slice(value);
                }
            }
        }
        let Some(table) = &mut self.table else { return Ok(()) };
        table.column += 1;
        if table.column == table.items.len() && self.table_is_loop {
            table.column = 0;
            self.end_row(line)?;
        }
        Ok(())
    }

    fn end_table(&mut self, line: u64) -> Result<(), Error> {
        if let Some(tag) = self.pair_tag.take() {
            return Err(self.malformed(line, format!("{} has no value", quote(&tag))));
        }
        if self.loop_tags.take().is_some_and(|tags| !tags.is_empty()) {
            // A loop with tags and no values: an empty table.
            return Ok(());
        }
        let Some(table) = &self.table else { return Ok(()) };
        if self.table_is_loop {
            if table.column != 0 {
                let (columns, left) = (table.items.len(), table.column);
                let name =
                    String::from_utf8_lossy(table.items.first().map(Vec::as_slice).unwrap_or_default()).into_owned();
                return Err(self.malformed(
                    line,
                    format!(
                        "loop of {name}... ends {left} values into a row of {columns}: values missing (truncated?)"
                    ),
                ));
            }
        } else {
            self.end_row(line)?;
        }
        self.table = None;
        Ok(())
    }

    fn end_row(&mut self, line: u64) -> Result<(), Error> {
        let Some(table) = &self.table else { return Ok(()) };
        match table.category {
            Category::AtomSite => self.atom_row(line),
            Category::OperList => self.operator_row(line),
            Category::AssemblyGen => {
                let cell = |name: &[u8]| -> String {
                    table
                        .items
                        .iter()
                        .position(|i| i.eq_ignore_ascii_case(name))
                        .and_then(|at| table.text_row.get(at))
                        .map(|v| String::from_utf8_lossy(v).into_owned())
                        .unwrap_or_default()
                };
                let chains =
                    cell(b"asym_id_list").split(',').map(|c| c.trim().to_owned()).filter(|c| !c.is_empty()).collect();
                let generator =
                    AssemblyGen { line, assembly: cell(b"assembly_id"), expression: cell(b"oper_expression"), chains };
                self.generators.push(generator);
                Ok(())
            }
            Category::Other => Ok(()),
        }
    }

    fn atom_row(&mut self, line: u64) -> Result<(), Error> {
        let missing = [AtomColumn::X, AtomColumn::Y, AtomColumn::Z].into_iter().zip(self.row.has).find(|(_, has)| !has);
        if let Some((column, _)) = missing {
            return Err(self.malformed(line, format!("_atom_site row has no {}", column.field())));
        }
        let row = &self.row;
        if !row.model.is_empty() && !is_null(&row.model) {
            match &self.first_model {
                None => {
                    self.atoms.set_model_if(true, parse_count(&row.model).ok());
                    self.first_model = Some(row.model.clone());
                }
                Some(first) if *first == row.model => {}
                Some(_) => {
                    self.other_model_atoms += 1;
                    return Ok(());
                }
            }
        }
        if !row.alt.is_empty() && !is_null(&row.alt) {
            match &self.first_alt {
                None => self.first_alt = Some(row.alt.clone()),
                Some(first) if *first == row.alt => {}
                Some(_) => {
                    self.other_alt_atoms += 1;
                    return Ok(());
                }
            }
        }
        let element = if let Some(element) = Element::from_symbol(&row.symbol) {
            element
        } else {
            let element = element_from_bare_name(&row.name, &row.residue);
            let (symbol, name) = (quote(&row.symbol), quote(&row.name));
            self.atoms.warn(line, || {
                format!("type_symbol {symbol:?} is not an element; {} from atom name {name:?}", element.symbol())
            });
            element
        };
        let chain_id = if row.asym.is_empty() || is_null(&row.asym) { &row.auth_asym } else { &row.asym };
        let chain_id: &[u8] = if is_null(chain_id) { b"" } else { chain_id };
        let chain = self.atoms.chain(chain_id, line)?;
        let number = if value(&row.auth_seq).is_empty() { &row.label_seq } else { &row.auth_seq };
        let fields = FieldsIn {
            name: value(&row.name),
            residue: value(&row.residue),
            residue_number: optional(&mut self.atoms, ("_atom_site", "auth_seq_id"), value(number), line, |t| {
                t.parse().ok()
            }),
            insertion_code: value(&row.ins_code).first().copied(),
            b_factor: optional(&mut self.atoms, ("_atom_site", "B_iso_or_equiv"), value(&row.b_factor), line, finite),
            occupancy: optional(&mut self.atoms, ("_atom_site", "occupancy"), value(&row.occupancy), line, finite),
            hetero: row.group.eq_ignore_ascii_case(b"HETATM"),
        };
        self.atoms.push(row.xyz, element, chain, &fields, line)?;
        self.row.clear();
        Ok(())
    }
}

/// Reads an mmCIF file's atoms (first model) and assemblies.
pub(crate) fn read(lines: &mut Lines<'_>, limits: &Limits, want_assembly: bool) -> Result<Molecule, Error> {
    let file = lines.file();
    let mut reader = Reader {
        file,
        atoms: Builder::new(file, limits),
        row: AtomRow::default(),
        first_model: None,
        other_model_atoms: 0,
        first_alt: None,
        other_alt_atoms: 0,
        operators: HashMap::new(),
        operator_order: Vec::new(),
        generators: Vec::new(),
        loop_tags: None,
        pair_tag: None,
        table: None,
        table_is_loop: false,
        data_blocks: 0,
    };
    // A text field: its text so far and the line it started on.
    let mut text_field: Option<(Vec<u8>, u64)> = None;
    let mut more_blocks = false;
    while let Some((line, text)) = lines.next_line()? {
        let mut rest = text;
        if let Some((field, start)) = &mut text_field {
            if let Some(after) = text.strip_prefix(b";") {
                let value = std::mem::take(field);
                let start = *start;
                text_field = None;
                reader.token(Token::Value(&value), start)?;
                rest = after;
            } else {
                if field.len() < limits.max_line_bytes {
                    field.extend_from_slice(text);
                    field.push(b'\n');
                }
                continue;
            }
        } else if let Some(after) = text.strip_prefix(b";") {
            text_field = Some((after.to_vec(), line));
            continue;
        }
        let mut error = None;
        let tokenized = tokens(rest, |token| {
            if token == Token::Data && reader.data_blocks >= 1 {
                more_blocks = true;
                return Err(String::new());
            }
            reader.token(token, line).map_err(|e| {
                error = Some(e);
                String::new()
            })
        });
        if let Some(e) = error {
            return Err(e);
        }
        if more_blocks {
            break;
        }
        if let Err(why) = tokenized {
            return Err(reader.malformed(line, why));
        }
    }
    let last = lines.line();
    if last == 0 {
        return Err(Error::NoAtoms { file: file.to_owned(), why: "the file is empty" });
    }
    if let Some((_, start)) = text_field {
        return Err(reader.malformed(start, "text field (;) never closed".to_owned()));
    }
    reader.end_table(last)?;
    if more_blocks {
        reader.atoms.warn(0, || "more than one data block: only the first is read".to_owned());
    }
    if reader.other_model_atoms > 0 {
        let skipped = reader.other_model_atoms;
        reader
            .atoms
            .warn(0, || format!("several models; only the first is read ({skipped} atoms of later models skipped)"));
    }
    if reader.other_alt_atoms > 0 {
        let (skipped, kept) = (reader.other_alt_atoms, quote(reader.first_alt.as_deref().unwrap_or_default()));
        reader.atoms.warn(0, || format!("alternate locations other than {kept:?}: {skipped} atoms skipped"));
    }
    let assemblies = match reader.assemblies() {
        Ok(assemblies) => assemblies,
        Err(e) if !want_assembly => {
            reader.atoms.warn(0, || format!("assemblies ignored: {e}"));
            Vec::new()
        }
        Err(e) => return Err(e),
    };
    reader.atoms.finish(Format::Mmcif, assemblies, "no _atom_site rows")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Four atoms of 1TII's chain D (pymol-data's 1tii.pdb, atoms 1 to 4), as mmCIF writes them,
    /// a fifth atom in model 2, and a 2-operator assembly for chain A.
    pub(super) const SMALL: &str = "\
data_1TII
#
_entry.id 1TII
#
loop_
_atom_site.group_PDB
_atom_site.id
_atom_site.type_symbol
_atom_site.label_atom_id
_atom_site.label_alt_id
_atom_site.label_comp_id
_atom_site.label_asym_id
_atom_site.auth_asym_id
_atom_site.Cartn_x
_atom_site.Cartn_y
_atom_site.Cartn_z
_atom_site.pdbx_PDB_model_num
ATOM 1 N N   . GLY A D 42.053 -9.336  17.867 1
ATOM 2 C CA  . GLY A D 42.704 -10.253 18.851 1
ATOM 3 C C   . GLY A D 44.140 -10.512 18.447 1
ATOM 4 O O   . GLY A D 44.962 -10.836 19.303 1
ATOM 5 O O   . GLY A D 0.0 0.0 0.0 2
#
_pdbx_struct_assembly_gen.assembly_id       1
_pdbx_struct_assembly_gen.oper_expression   (1,2)
_pdbx_struct_assembly_gen.asym_id_list      A
#
loop_
_pdbx_struct_oper_list.id
_pdbx_struct_oper_list.type
_pdbx_struct_oper_list.matrix[1][1]
_pdbx_struct_oper_list.matrix[1][2]
_pdbx_struct_oper_list.matrix[1][3]
_pdbx_struct_oper_list.vector[1]
_pdbx_struct_oper_list.matrix[2][1]
_pdbx_struct_oper_list.matrix[2][2]
_pdbx_struct_oper_list.matrix[2][3]
_pdbx_struct_oper_list.vector[2]
_pdbx_struct_oper_list.matrix[3][1]
_pdbx_struct_oper_list.matrix[3][2]
_pdbx_struct_oper_list.matrix[3][3]
_pdbx_struct_oper_list.vector[3]
1 'identity operation'         1 0 0 0  0 1 0 0  0 0 1 0
2 'crystal symmetry operation' -1 0 0 10  0 -1 0 0  0 0 1 5
#
";

    pub(super) fn read_text(text: &str, want_assembly: bool) -> Result<Molecule, Error> {
        let mut lines = Lines::new("t.cif", Box::new(text.as_bytes()), &Limits::default())?;
        read(&mut lines, &Limits::default(), want_assembly)
    }

    #[test]
    fn atom_site_gives_atoms_of_the_first_model() {
        let m = read_text(SMALL, false).unwrap();
        assert_eq!(m.len(), 4, "model 2 skipped");
        assert_eq!(m.positions()[0], glam::Vec3::new(42.053, -9.336, -17.867), "(x, y, -z)");
        assert_eq!(m.elements(), [Element::N, Element::C, Element::C, Element::O], "type_symbol");
        assert_eq!(m.chain_ids(), ["A"], "label_asym_id");
        assert_eq!(m.warnings().len(), 1, "{:?}", m.warnings());
        assert!(m.warnings()[0].message.contains("only the first"), "{:?}", m.warnings());
    }

    #[test]
    fn each_atoms_fields_from_atom_site() {
        let text = "\
data_1CRN
loop_
_atom_site.group_PDB
_atom_site.type_symbol
_atom_site.label_atom_id
_atom_site.label_comp_id
_atom_site.label_asym_id
_atom_site.label_seq_id
_atom_site.auth_seq_id
_atom_site.pdbx_PDB_ins_code
_atom_site.Cartn_x
_atom_site.Cartn_y
_atom_site.Cartn_z
_atom_site.occupancy
_atom_site.B_iso_or_equiv
_atom_site.pdbx_PDB_model_num
ATOM   N N   THR A 1 1 ? 17.047 14.099 3.625 1.00 13.79 1
ATOM   C CA  THR A 1 7 B 16.967 12.784 4.338 0.5 10.80 1
HETATM O O   HOH B . . ? 1.0 2.0 3.0 . . 1
";
        let m = read_text(text, false).unwrap();
        let a = m.atom(0).unwrap();
        assert_eq!((a.name, a.residue_name, a.residue_number, a.insertion_code), ("N", "THR", Some(1), None), "first");
        assert_eq!((a.b_factor, a.occupancy, a.hetero, a.model), (Some(13.79), Some(1.0), false, Some(1)), "numbers");
        let b = m.atom(1).unwrap();
        assert_eq!((b.residue_number, b.insertion_code, b.occupancy), (Some(7), Some('B'), Some(0.5)), "auth_seq_id");
        let w = m.atom(2).unwrap();
        assert_eq!((w.residue_name, w.residue_number, w.b_factor, w.hetero), ("HOH", None, None, true), "nulls");
        assert!(m.warnings().is_empty(), "{:?}", m.warnings());
    }

    #[test]
    fn struct_oper_list_and_assembly_gen_give_the_assembly() {
        let m = read_text(SMALL, true).unwrap();
        let a = &m.assemblies()[0];
        assert_eq!((a.id.as_str(), a.parts[0].chains.as_slice()), ("1", &["A".to_owned()][..]), "id and chains");
        assert_eq!(a.parts[0].operators.len(), 2, "(1,2)");
        let big = m.expand_assembly(0, &Limits::default()).unwrap();
        assert_eq!(big.len(), 8, "two copies");
        // Operator 2 on file (42.053, -9.336, 17.867): (10 - 42.053, 9.336, 17.867 + 5).
        assert!(
            big.positions()[4].abs_diff_eq(glam::Vec3::new(-32.053, 9.336, -22.867), 1e-5),
            "{}",
            big.positions()[4]
        );
    }

    #[test]
    fn malformed_mmcif_names_line_and_field() {
        let e = read_text(&SMALL.replace("-10.253", "-10.2x3"), false).unwrap_err();
        assert_eq!(e.to_string(), r#"t.cif:19: _atom_site Cartn_y = "-10.2x3": not a number"#, "bad number");
        let e = read_text(&SMALL.replace("0.0 0.0 0.0 2\n", "0.0 0.0 0.0\n"), false).unwrap_err();
        // The last row is one value short: the loop ends at the next tag, mid-row.
        assert_eq!(
            e.to_string(),
            "t.cif:24: loop of group_PDB... ends 11 values into a row of 12: values missing (truncated?)",
            "a short last row"
        );
        let e = read_text("data_x\n_atom_site.Cartn_x 1\n_atom_site.Cartn_y 2\n", false).unwrap_err();
        assert_eq!(e.to_string(), "t.cif:3: _atom_site row has no Cartn_z", "pairs without z");
        let truncated: String =
            SMALL.lines().take(21).flat_map(|l| [l, "\n"]).collect::<String>() + "ATOM 4 O O . GLY A D 44.962\n";
        let e = read_text(&truncated, false).unwrap_err();
        assert!(e.to_string().starts_with("t.cif:22: loop of group_PDB... ends 9 values into a row of 12"), "{e}");
        let e = read_text(&SMALL.replace("_atom_site.Cartn_z\n", ""), false).unwrap_err();
        assert_eq!(e.to_string(), "t.cif:17: _atom_site loop has no Cartn_z", "missing column");
        let e = read_text("data_x\n_cell.length_a\n", false).unwrap_err();
        assert!(e.to_string().contains("has no value"), "{e}");
        let e = read_text("data_x\n;\nnever closed\n", false).unwrap_err();
        assert_eq!(e.to_string(), "t.cif:2: text field (;) never closed", "open text field");
        let e = read_text("data_x\n_entry.id 1TII\n", false).unwrap_err();
        assert_eq!(e.to_string(), "t.cif: no atoms: no _atom_site rows", "no atoms");
    }

    #[test]
    fn text_fields_and_pairs_are_values() {
        let text = "data_x\n_struct.title\n;A title\nover two lines\n;\n_atom_site.Cartn_x 1\n_atom_site.Cartn_y 2\n_atom_site.Cartn_z 3\n_atom_site.type_symbol Fe\n";
        let m = read_text(text, false).unwrap();
        assert_eq!(m.len(), 1, "a single atom as item-value pairs");
        assert_eq!(m.positions()[0], glam::Vec3::new(1.0, 2.0, -3.0), "its coordinates");
        assert_eq!(m.elements()[0].symbol(), "Fe", "its element");
    }
}
